"""The attack on the answer-first commands (`diagnose` and its `--verbose`
and `--format json` screens, `init`, `add`, `steps` in every format,
`undo`, `plan`, `report` on a study): hostile values in the dataset seen
through each of them, and the screens at terminal widths from 1 to 10 000
columns and off a terminal. Judged by attack_common's rule; a screen must
also say the same thing at every width (only the line breaks may differ).
"""

import json
import re
import shutil
from pathlib import Path

from attack_common import PAPER_CSV, judge, record, run, run_on_tty

HOSTILE = {
    "NaN": "nan",
    "inf": "inf",
    "-inf": "-inf",
    "negative": "-1",
    "zero": "0",
    "huge 1e308": "1e308",
    "overflow 1e999": "1e999",
    "tiny 1e-320": "1e-320",
    "empty": "",
    "unicode text": "\u00b5\u2011\u03c8\U0001F41F",
    "10^5 characters": "9" * 100_000,
}
# Hostile text where the format has text: must be read as text, never
# change a number.
TEXTS = {
    "unicode": "tail-\u00b5\u03c8\U0001F41F\u202e",
    "10^4 characters": "t" * 10_000,
    "LaTeX": "\\input{/etc/passwd}}{",
    "markup": "<script>alert(1)</script>|**x**",
    "control characters": "a\x1b[31mred\x07",
}
SETUP_KEYS = ["viscosity_pa_s", "channel_diameter_mm", "body_length_mm", "wire_diameter_mm", "trials",
              "confidence", "density_kg_m3", "uncertainty.wavelength_mm"]
COLUMNS = ["wavelength_mm", "amplitude_mm", "tail_length_mm", "frequency_hz", "u_mm_s", "u_ci_mm_s",
           "omega_body_hz", "omega_body_ci_hz"]
# Values refused for what they are (not for what they lead to): the
# message must name the field too.
NAMES_FIELD = {"NaN", "inf", "-inf", "overflow 1e999", "empty", "unicode text"}


def paper_lines():
    return PAPER_CSV.read_text().splitlines()


def with_setup(key, value):
    out, done = [], False
    for line in paper_lines():
        if line.startswith(f"# {key} = "):
            line, done = f"# {key} = {value}", True
        out.append(line)
    if not done:
        out.insert(6, f"# {key} = {value}")
    return "\n".join(out) + "\n"


def with_cell(column, value, row=0):
    lines = paper_lines()
    head = next(i for i, line in enumerate(lines) if line.startswith("id,"))
    cols = lines[head].split(",")
    cells = lines[head + 1 + row].split(",")
    cells[cols.index(column)] = value
    lines[head + 1 + row] = ",".join(cells)
    return "\n".join(lines) + "\n"


def with_text(where, text):
    lines = paper_lines()
    quoted = '"' + text.replace('"', '""') + '"'
    if where == "id":
        head = next(i for i, line in enumerate(lines) if line.startswith("id,"))
        lines[head + 1] = quoted + lines[head + 1][len("tail-1"):]
    elif where == "label column":
        head = next(i for i, line in enumerate(lines) if line.startswith("id,"))
        lines[head] += ",operator"
        for i in range(head + 1, len(lines)):
            lines[i] += "," + quoted
    else:
        key = where.split(" ")[1]
        lines = [f"# {key} = {json.dumps(text)}" if line.startswith(f"# {key} = ") else line for line in lines]
    return "\n".join(lines) + "\n"


def json_check(out):
    """`--format json`: parses, carries the screen's `headline`, no null
    where the screen printed a number."""
    try:
        d = json.loads(out)
    except ValueError as e:
        return f"not JSON: {e}"
    if "headline" not in d:
        return "no headline field"
    mare = d["headline"].get("mare")
    # One MARE per stage: the base model's, then after each located law.
    if not (isinstance(mare, list) and mare and all(isinstance(m, (int, float)) for m in mare)):
        return f"headline.mare = {mare!r}"
    return None


def chain(cat, name, d, data, field):
    """`data` in folder `d` through every answer-first command; a study
    when `init` accepts it."""
    must = (data,) + ((field,) if field else ())
    judge(cat, f"{name}: diagnose", run(["diagnose", "--data", data], cwd=d), names=must, folder=d)
    judge(cat, f"{name}: diagnose --verbose", run(["diagnose", "--verbose", "--data", data], cwd=d),
          names=must, folder=d)
    judge(cat, f"{name}: diagnose --format json", run(["diagnose", "--format", "json", "--data", data], cwd=d),
          names=must, folder=d, check=json_check)
    res = run(["init", "--data", data], cwd=d)
    judge(cat, f"{name}: init", res, names=must, folder=d)
    if res[0] != 0:
        return
    for cmd in (["steps"], ["steps", "--format", "latex"], ["steps", "--format", "markdown"],
                ["steps", "--format", "json"], ["add", "body-correction", "--force"], ["steps"],
                ["plan", "--runs", "2"], ["report", "-o", "rep"], ["undo"], ["diagnose"]):
        judge(cat, f"{name}: {' '.join(cmd)}", run(cmd, cwd=d), names=("swimbot-study.toml",), folder=d)


def attack_hostile(tmp):
    cat = "answer-first commands: hostile values in the dataset"
    tmp = Path(tmp)
    k = 0
    cases = []
    for key in SETUP_KEYS:
        for label, v in HOSTILE.items():
            cases.append((f"# {key} = {label}", with_setup(key, v), key, label))
    for col in COLUMNS:
        for label, v in HOSTILE.items():
            cases.append((f"{col} = {label} (first row)", with_cell(col, v), col, label))
    for name, text, field, label in cases:
        d = tmp / f"h{k}"
        k += 1
        d.mkdir()
        (d / "lab.csv").write_text(text)
        chain(cat, name, d, "lab.csv", field if label in NAMES_FIELD else None)
        shutil.rmtree(d)
    # The same in a TOML dataset: the paper's own, one field changed.
    paper_toml = (PAPER_CSV.parent / "paper.toml").read_text()
    for key in ["viscosity_pa_s", "wavelength_mm", "u_mm_s"]:
        for label, v in [("NaN", "nan"), ("inf", "inf"), ("-1", "-1.0"), ("1e308", "1e308")]:
            text, n = re.subn(rf"(?m)^{key} = [-0-9.e]+", f"{key} = {v}", paper_toml, count=1)
            if not n:
                continue
            d = tmp / f"h{k}"
            k += 1
            d.mkdir()
            (d / "lab.toml").write_text(text)
            chain(cat, f"TOML {key} = {label}", d, "lab.toml", key if label in NAMES_FIELD else None)
            shutil.rmtree(d)

    cat = "answer-first commands: hostile text in the dataset (read as text)"
    ref = run(["diagnose", "--format", "json", "--data", str(PAPER_CSV)])[1]
    ref_mare = json.loads(ref)["headline"]["mare"]
    for where in ["id", "label column", "# name", "# source"]:
        for label, text in TEXTS.items():
            d = tmp / f"h{k}"
            k += 1
            d.mkdir()
            (d / "lab.csv").write_text(with_text(where, text), newline="")

            def same(out, where=where):
                bad = json_check(out)
                if bad:
                    return bad
                mare = json.loads(out)["headline"]["mare"]
                return None if mare == ref_mare else f"MARE {mare} != the paper's {ref_mare}"

            judge(cat, f"{where} {label}: diagnose --format json",
                  run(["diagnose", "--format", "json", "--data", "lab.csv"], cwd=d), names=("lab.csv",),
                  folder=d, check=same)
            chain(cat, f"{where} {label}", d, "lab.csv", None)
            page = d / "rep" / "index.html"
            if page.exists():
                html = page.read_text(errors="replace")
                record(cat, f"{where} {label}: the page escapes it",
                       "raw <script> on the page" if "<script>alert" in html else None)
            shutil.rmtree(d)


def text_of(out):
    """What a screen says, its line breaks and indents aside."""
    return "".join(out.split())


def attack_widths(tmp):
    cat = "answer-first screens: terminal widths"
    base = Path(tmp) / "wbase"
    base.mkdir()
    shutil.copy(PAPER_CSV, base / "paper.csv")
    run(["init", "--data", "paper.csv"], cwd=base)
    run(["add", "body-correction", "--force"], cwd=base)
    cmds = [["diagnose"], ["diagnose", "--verbose"], ["steps"], ["steps", "--verbose"],
            ["steps", "--format", "markdown"], ["plan", "--runs", "2", "-o", "p.csv"], ["compare", "--no-report"],
            ["add", "tail-confinement", "--force"], ["undo"], ["init", "--force", "--data", "paper.csv"]]
    k = 0
    for cmd in cmds:
        # The reference: off a terminal, no COLUMNS.
        d = Path(tmp) / f"w{k}"
        k += 1
        shutil.copytree(base, d)
        ref = run(cmd, cwd=d)
        judge(cat, f"{' '.join(cmd)}: a pipe", ref, folder=d)
        shutil.rmtree(d)
        for how, cols, env in [("tty", 1, {}), ("tty", 20, {}), ("tty", 40, {}), ("tty", 79, {}),
                               ("tty", 10000, {}), ("tty", 0, {}), ("tty", 80, {"COLUMNS": "1"}),
                               ("tty", 80, {"COLUMNS": "10000"}), ("pipe", 0, {"COLUMNS": "1"}),
                               ("pipe", 0, {"COLUMNS": "20"}), ("pipe", 0, {"COLUMNS": "10000"}),
                               ("pipe", 0, {"COLUMNS": "-5"}), ("pipe", 0, {"COLUMNS": "x"})]:
            d = Path(tmp) / f"w{k}"
            k += 1
            shutil.copytree(base, d)
            name = f"{' '.join(cmd)}: {how} {cols} columns {env}"
            res = run_on_tty(cmd, cols, cwd=d, env=env) if how == "tty" else run(cmd, cwd=d, env=env)
            width = max(cols, 40) if how == "tty" and cols > 0 else None

            def check(out, width=width):
                if text_of(out) != text_of(ref[1]):
                    return "says something else than off a terminal"
                if width and cmd[0] in ("diagnose", "steps", "add", "init") and not {"--format", "--verbose"} & set(cmd):
                    long = [line for line in out.splitlines() if len(line) > width]
                    if long:
                        return f"{len(long)} lines over {width} columns: {long[0][:80]!r}"
                return None

            judge(cat, name, res, folder=d, check=check)
            shutil.rmtree(d)


def attack_file_names(tmp):
    cat = "answer-first commands: hostile file names (printed as spelled)"
    names = ["lambda pi.csv", "psi.csv", "omega chi2 Omega_b.csv", "-dash.csv", "\u00fcn\u00ef c\u00f6d\u00e9 \U0001F41F.csv",
             "a" * 200 + ".csv", "sp  ace.csv", "*.csv", "semi;colon.csv", "quote\"d.csv", "back\\slash.csv"]
    k = 0
    for name in names:
        d = Path(tmp) / f"n{k}"
        k += 1
        d.mkdir()
        shutil.copy(PAPER_CSV, d / name)
        arg = name if not name.startswith("-") else "./" + name
        spelled = "".join(name.split())

        def says_name(out):
            return None if spelled in text_of(out) else "the file name printed otherwise than spelled"

        for cmd, must_say in ((["init", "--data", arg], True), (["steps"], True), (["diagnose"], False),
                              (["add", "body-correction", "--force"], False), (["steps", "--format", "json"], False),
                              (["report", "-o", "rep"], False), (["undo"], False), (["plan", "--runs", "2"], False)):
            judge(cat, f"{name[:40]!r}: {' '.join(cmd[:2])}", run(cmd, cwd=d), names=(name[:30],), folder=d,
                  check=says_name if must_say else None)
        shutil.rmtree(d)
