"""The attack on where the answer-first commands write and what their
tables let through: `plan -o`, `report -o`, `diagnose --write-effect`,
`init --study` and stdout aimed at the inputs, /dev/full, read-only and
missing folders; text that reaches `steps --format latex|markdown` (a
`\\input{...}` or an unbalanced brace must come out escaped, a `|` or a
line break must not split a row); and `plan`'s flags. Judged by
attack_common's rule.
"""

import os
import re
import shutil
from pathlib import Path

from attack_common import PAPER_CSV, judge, record, run, run_as_nobody, run_to, snapshot

STUDY = "swimbot-study.toml"


def study_base(tmp):
    base = Path(tmp) / "obase"
    base.mkdir()
    shutil.copy(PAPER_CSV, base / "paper.csv")
    assert run(["init", "--data", "paper.csv"], cwd=base)[0] == 0
    assert run(["add", "body-correction", "--force"], cwd=base)[0] == 0
    (base / "notes").mkdir()
    (base / "notes" / "mine.txt").write_text("the user's own file\n")
    return base


def fresh(base, tmp, name):
    d = Path(tmp) / name
    shutil.copytree(base, d)
    return d


def targets(d):
    """(label, path as given) of output places to aim at."""
    (d / "ro").mkdir()
    os.chmod(d / "ro", 0o555)
    os.mkfifo(d / "fifo")
    (d / "link-to-data").symlink_to("paper.csv")
    (d / "dangling").symlink_to("nowhere/x")
    return [
        ("the dataset", "paper.csv"), ("the dataset by ./", "./paper.csv"), ("the dataset by sub/..", "notes/../paper.csv"),
        ("the study file", STUDY), ("a symlink to the dataset", "link-to-data"), ("the user's file", "notes/mine.txt"),
        ("/dev/full", "/dev/full"), ("/dev/null", "/dev/null"), ("a FIFO", "fifo"), ("a read-only folder", "ro/x"),
        ("a missing folder", "missing/deep/x"), ("new/../notes", "new/../notes/x"), ("empty", ""),
        ("a dangling symlink", "dangling"), ("a folder", "notes"), ("the working folder", "."),
        ("/proc", "/proc/self/x"), ("a name of 300 bytes", "n" * 300), ("a path of 5000 bytes", "/".join(["d"] * 2500)),
    ]


def judge_write(cat, name, res, d, before, out, kind):
    """A refusal must name the output and leave the folder as it was; a
    success must leave the inputs (the dataset, the study unless `init
    --force` was aimed at it) and every other file in place."""
    inputs = ["paper.csv"] + ([] if kind.startswith("init --force") and out == STUDY else [STUDY])

    def kept(_out):
        after = snapshot(d)
        changed = [k for k in inputs if before.get(k) != after.get(k)]
        lost = [k for k in before if k not in after]
        if changed:
            return f"accepted, and changed the input {changed[:3]}"
        return f"accepted, and removed {lost[:3]}" if lost else None

    judge(cat, name, res, names=(out[:40],) if out else (), before=before, folder=d, check=kept)


def attack_outputs(tmp):
    cat = "answer-first commands: outputs onto inputs, devices, read-only and missing folders"
    base = study_base(tmp)
    k = 0
    makers = {
        "plan -o": lambda o: ["plan", "--runs", "2", "-o", o],
        "report -o": lambda o: ["report", "-o", o],
        "diagnose --write-effect": lambda o: ["diagnose", "--write-effect", o],
        "init --study": lambda o: ["--study", o, "init", "--data", "paper.csv"],
        "init --force --study": lambda o: ["--study", o, "init", "--force", "--data", "paper.csv"],
    }
    for kind, make in makers.items():
        for label, out in targets(fresh(base, tmp, "probe")):
            d = fresh(base, tmp, f"o{k}")
            k += 1
            targets(d)
            before = snapshot(d)
            cmd = make(out)
            if label == "a read-only folder":
                res = run_as_nobody(cmd, cwd=d)
            else:
                res = run(cmd, cwd=d, timeout=60)
            judge_write(cat, f"{kind} {label}", res, d, before, out, kind)
            os.chmod(d / "ro", 0o755)
            shutil.rmtree(d)
        shutil.rmtree(Path(tmp) / "probe")
    # stdout itself: a full disk must fail the run, saying so; a regular
    # file is written whole.
    for cmd in (["diagnose"], ["diagnose", "--verbose"], ["diagnose", "--format", "json"], ["steps"],
                ["steps", "--format", "latex"], ["steps", "--format", "markdown"], ["steps", "--format", "csv"],
                ["steps", "--format", "json"], ["plan", "--runs", "2", "-o", "p.csv"], ["add", "tail-confinement"],
                ["undo"], ["init", "--force", "--data", "paper.csv"]):
        d = fresh(base, tmp, f"o{k}")
        k += 1
        before = snapshot(d)
        res = run_to(cmd, "/dev/full", cwd=d)
        why = judge(cat, f"{' '.join(cmd)} > /dev/full", res, names=("standard output",), folder=d, accept_ok=False)
        if not why and cmd[0] in ("add", "undo", "init") and snapshot(d) != before:
            # The study changed and the user was told it failed.
            record(cat, f"{' '.join(cmd)} > /dev/full: study", "the study changed under an error", res[0], res[2])
        shutil.rmtree(d)
    # An output that is a missing folder: made, and only what the run made
    # is removed when it fails.
    d = fresh(base, tmp, f"o{k}")
    (d / "paper.csv").write_text((d / "paper.csv").read_text().replace("0.586", "0.587"))
    before = snapshot(d)
    res = run(["report", "-o", "new/../notes"], cwd=d)
    judge(cat, "report -o new/../notes on a changed dataset (refused)", res, names=(STUDY,), before=before, folder=d)
    record(cat, "report -o new/../notes refused: notes/ still there",
           None if (d / "notes" / "mine.txt").exists() else "the user's folder is gone")


# --- the paper's tables ------------------------------------------------------

PAYLOADS = {
    "\\input": "\\input{/etc/passwd}",
    "unbalanced brace": "x}}{",
    "\\write18": "\\immediate\\write18{rm -rf ~}",
    "markdown pipe": "a|b|c",
    "line break": "a\nb",
    "blank line": "a\n\nb",
    "html": "<script>alert(1)</script>",
    "backtick": "`x`",
    "dollar": "$\\x$",
}


def latex_check(out):
    rows = [line for line in out.splitlines() if line.endswith("\\\\")]
    body = "\n".join(out.splitlines())
    if re.search(r"(?<!textbackslash\{\})\\(input|include|write|immediate|def|catcode)\b", body):
        return "a LaTeX command from the input emitted raw"
    depth = 0
    for m in re.finditer(r"\\\\|\\[{}]|[{}]", body):
        t = m.group()
        depth += {"{": 1, "}": -1}.get(t, 0)
        if depth < 0:
            return "a closing brace with no opening one"
    if depth:
        return "unbalanced braces"
    if not rows or any(line.count("&") - line.count("\\&") != 5 for line in rows[1:]):
        return "a row with another number of cells"
    return None


def markdown_check(out):
    lines = out.splitlines()
    rows = [line for line in lines[2:] if line]
    if any(not (line.startswith("| ") and line.endswith(" |")) for line in rows):
        return "a line that is not a table row"
    if any(len(re.findall(r"(?<!\\)\|", line)) != 7 for line in rows):
        return "a row with another number of cells"
    if "<script" in out:
        return "raw HTML from the input"
    return None


def attack_tables(tmp):
    cat = "steps --format latex|markdown: text from effects files and the study"
    base = study_base(tmp)
    law = ('[[effect]]\nname = "{name}"\nstatement = "{text}"\nreference = "{text}"\napplies_to = "all cases"\n'
           '[[effect.param]]\nname = "{param}"\nunit = "{text}"\ndefault = 1.0\nmin = 0.02\nmax = 50.0\n'
           'free = true\ndoc = "{text}"\n[effect.places]\n"tail.torque" = "{param} * (pitch_angle_deg / 67.0)^0.5"\n')
    k = 0
    esc = lambda s: s.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n")  # noqa: E731
    for label, text in PAYLOADS.items():
        for where in ("name", "param", "text"):
            d = fresh(base, tmp, f"t{k}")
            k += 1
            fields = {"name": "mine", "param": "k", "text": "a law"}
            fields[where] = esc(text)
            body = law.format(**fields)
            (d / "law.toml").write_text(body)
            before = snapshot(d)
            res = run(["add", "law.toml", "--force"], cwd=d)
            judge(cat, f"{label} in the effect's {where}: add", res, names=("law.toml",), before=before, folder=d)
            for fmt, check in (("latex", latex_check), ("markdown", markdown_check)):
                judge(cat, f"{label} in the effect's {where}: steps --format {fmt}",
                      run(["steps", "--format", fmt], cwd=d), folder=d, check=check)
            shutil.rmtree(d)
    # The same text put into the study by hand.
    text = (base / STUDY).read_text()
    spots = {
        "preset": (r'(?m)^preset = "base"', 'preset = "{}"'),
        "dataset name": (r'(?m)^name = "tabak-yesilyurt-vertical"', 'name = "{}"'),
        "step effect name": (r'(?m)^name = "body-correction"', 'name = "{}"'),
        "param name": (r'(?m)^name = "translation"', 'name = "{}"'),
        "param unit": (r'(?m)^unit = "1"', 'unit = "{}"'),
        "param reason": (r'(?m)^reason = ".*"', 'reason = "{}"'),
        "refit": (r'(?m)^refit = ".*"', 'refit = "{}"'),
        "statement": (r'(?m)^statement = ".*"', 'statement = "{}"'),
    }
    for label, payload in PAYLOADS.items():
        for spot, (pat, repl) in spots.items():
            mutant, n = re.subn(pat, repl.format(esc(payload)).replace("\\", "\\\\"), text, count=1)
            if not n:
                continue
            d = fresh(base, tmp, f"t{k}")
            k += 1
            (d / STUDY).write_text(mutant)
            before = snapshot(d)
            for fmt, check in (("latex", latex_check), ("markdown", markdown_check)):
                judge(cat, f"{label} in the study's {spot}: steps --format {fmt}",
                      run(["steps", "--format", fmt], cwd=d), names=(STUDY,), before=before, folder=d, check=check)
            judge(cat, f"{label} in the study's {spot}: report", run(["report", "-o", "rep"], cwd=d),
                  names=(STUDY,), before=before, folder=d)
            page = d / "rep" / "index.html"
            if page.exists():
                record(cat, f"{label} in the study's {spot}: the page escapes it",
                       "raw <script> on the page" if "<script>alert" in page.read_text(errors="replace") else None)
            shutil.rmtree(d)


def attack_plan_flags(tmp):
    cat = "plan: flags"
    base = study_base(tmp)
    flags = [
        (["--runs", "-1"], "--runs"), (["--runs=-1"], "--runs"), (["--runs", "-0"], "--runs"), (["--runs", "0"], "--runs"),
        (["--runs", "1e3"], "--runs"), (["--runs", "x"], "--runs"), (["--runs", ""], "--runs"),
        (["--runs", "99999999999999999999999"], "--runs"), (["--runs", "2.5"], "--runs"), (["--runs", " 3"], "--runs"),
        (["--runs", "100000"], "--runs"),
    ]
    for flag in ("--tubes-mm", "--oils-pa-s"):
        for v in ["nan", "inf", "-inf", "-1", "0", "1e308", "1e-308", "", ",", "35,,45", "35,nan", "x", "1e999",
                  "35," * 2000 + "35", "-35", "\u00b5", "35;45", "35 45"]:
            flags.append(([f"{flag}={v}"], flag))
    flags += [(["--new-tails", "--tubes-mm=1e-3"], "--tubes-mm"), (["--new-tails", "--oils-pa-s=1e9"], "--oils-pa-s"),
              (["--new-tails", "--runs", "50"], "--runs")]
    k = 0
    for args, flag in flags:
        d = fresh(base, tmp, f"p{k}")
        k += 1
        before = snapshot(d)
        res = run(["plan", *args, "-o", "p.csv"], cwd=d, timeout=120)
        judge(cat, f"plan {' '.join(a[:40] for a in args)}", res, names=(flag,), before=before, folder=d)
        shutil.rmtree(d)
