"""What the scripted attacks (scripts/attack_surfaces.py and the modules it
runs) share: running the binary, a folder's fingerprint, and the judge that
applies one rule to every attempt (exit 0 with no NaN/inf printed, or exit 2
with `swimbot: error:` naming the file or field; never a panic, signal or
hang; a refused command leaves its folder byte for byte and no temporary
file behind). The tally is process-wide: one line per category at the end.
"""

import hashlib
import os
import re
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BIN = os.environ.get("SWIMBOT_BIN") or str(ROOT / "target" / "debug" / "swimbot")
PAPER_CSV = ROOT / "host" / "data" / "paper.csv"
TALLY = {}
FAULTS = []
NAN = re.compile(r"\b(nan|NaN|inf|-inf|Infinity)\b")


def run(args, cwd=None, timeout=120, env=None, stdin=None):
    e = dict(os.environ, NO_COLOR="1")
    e.update(env or {})
    try:
        p = subprocess.run(
            [BIN, *args], cwd=cwd, capture_output=True, text=True, timeout=timeout,
            env=e, stdin=stdin if stdin is not None else subprocess.DEVNULL,
        )
        return p.returncode, p.stdout, p.stderr
    except subprocess.TimeoutExpired:
        return "timeout", "", ""


def snapshot(folder):
    """Every file under `folder` with its SHA-256."""
    out = {}
    for p in sorted(Path(folder).rglob("*")):
        if p.is_file() and not p.is_symlink():
            out[str(p.relative_to(folder))] = hashlib.sha256(p.read_bytes()).hexdigest()
    return out


def judge(cat, name, result, names=(), before=None, folder=None, accept_ok=True, check=None):
    """Records one attempt; `names` must all appear in a refusal's message;
    `before` (a snapshot of `folder`) must equal the folder after a refusal."""
    rc, out, err = result
    TALLY.setdefault(cat, [0, 0])
    TALLY[cat][0] += 1
    why = None
    if rc == "timeout":
        why = "no answer within the time limit"
    elif "panicked" in err or "RUST_BACKTRACE" in err:
        why = "panic"
    elif rc == 0:
        if not accept_ok:
            why = "accepted"
        elif NAN.search(out):
            why = "NaN/inf printed"
        elif check is not None:
            why = check(out)
    elif rc == 2:
        if "swimbot: error:" not in err:
            why = "exit 2 without an error message"
        else:
            missing = [n for n in names if n not in err]
            if missing:
                why = f"message does not name {missing}"
    else:
        why = f"exit code {rc}"
    if why is None and folder is not None and before is not None and rc != 0:
        after = snapshot(folder)
        if after != before:
            why = f"files changed by a refused command: {sorted(set(after.items()) ^ set(before.items()))[:4]}"
    if why is None and folder is not None:
        tmp = [p.name for p in Path(folder).rglob("*") if ".tmp" in p.name]
        if tmp:
            why = f"temporary files left: {tmp[:3]}"
    if why:
        TALLY[cat][1] += 1
        FAULTS.append((cat, name, why, str(rc), err.strip()[-300:]))
    return why


def record(cat, name, why, rc="", err=""):
    """One attempt judged by its own check: `why` is None when it passed."""
    TALLY.setdefault(cat, [0, 0])
    TALLY[cat][0] += 1
    if why:
        TALLY[cat][1] += 1
        FAULTS.append((cat, name, why, str(rc), (err or "").strip()[-300:]))
    return why


def run_as_nobody(args, cwd, timeout=120):
    """`args` run as user nobody (root ignores a folder's permissions)."""
    try:
        r = subprocess.run(["setpriv", "--reuid=65534", "--regid=65534", "--clear-groups", BIN, *args],
                           cwd=cwd, capture_output=True, text=True, timeout=timeout,
                           env=dict(os.environ, NO_COLOR="1"), stdin=subprocess.DEVNULL)
        return r.returncode, r.stdout, r.stderr
    except subprocess.TimeoutExpired:
        return "timeout", "", ""


def run_to(args, stdout_path, cwd=None, timeout=120):
    """`args` with stdout written to `stdout_path` (/dev/full, a file)."""
    try:
        with open(stdout_path, "w") as out:
            r = subprocess.run([BIN, *args], cwd=cwd, stdout=out, stderr=subprocess.PIPE, text=True,
                               timeout=timeout, env=dict(os.environ, NO_COLOR="1"), stdin=subprocess.DEVNULL)
        return r.returncode, "", r.stderr
    except subprocess.TimeoutExpired:
        return "timeout", "", ""


def run_on_tty(args, cols, cwd=None, timeout=120, env=None):
    """`args` with stdout a pseudo-terminal `cols` columns wide (stderr a
    pipe): what a user at a terminal of that width sees."""
    import fcntl
    import pty
    import select
    import struct
    import termios
    import time

    master, slave = pty.openpty()
    fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 50, cols, 0, 0))
    e = dict(os.environ, NO_COLOR="1")
    e.update(env or {})
    p = subprocess.Popen([BIN, *args], cwd=cwd, stdout=slave, stderr=subprocess.PIPE,
                         stdin=subprocess.DEVNULL, env=e)
    os.close(slave)
    chunks, t0 = [], time.monotonic()
    while True:
        if time.monotonic() - t0 > timeout:
            p.kill()
            p.wait()
            os.close(master)
            return "timeout", "", ""
        r, _, _ = select.select([master], [], [], 0.2)
        if r:
            try:
                b = os.read(master, 65536)
            except OSError:
                b = b""
            if not b:
                break
            chunks.append(b)
        elif p.poll() is not None:
            # Drain what is left once the child is gone.
            continue
    p.wait()
    err = p.stderr.read().decode("utf-8", "replace")
    os.close(master)
    out = b"".join(chunks).decode("utf-8", "replace").replace("\r\n", "\n")
    return p.returncode, out, err
