"""The run-sheet loop attacked: `swimbot data add` on hand-edited filled
sheets (hostile cells, broken structure, hostile paths) and `swimbot sim
--plan` on hostile sheets and flags. Judged as every part is
(attack_common.judge): exit 0 with no NaN/inf printed and a study that
still opens, or exit 2 naming what is wrong with the study and every other
file byte for byte as they were.

    SWIMBOT_BIN=target/release/swimbot python3 scripts/attack_surfaces.py sheets
"""

import os
import shutil
from pathlib import Path

from attack_common import judge, run, snapshot

TRUTH = "base + body-confinement"
HOSTILE = ["nan", "inf", "-inf", "-1", "0", "1e308", "1e-308", "", "abc", "\u0663", "x" * 5000, "1,5", " 2 "]
COLUMNS = [
    "id", "frequency_hz", "u_mm_s", "u_ci_mm_s", "omega_body_hz", "omega_body_ci_hz", "trials",
    "channel_diameter_mm", "viscosity_pa_s", "body_diameter_mm", "tail_length_mm", "handedness",
    "labels.tail", "labels.set_point_hz", "density_kg_m3", "channel_closed",
]


def loop_base(tmp):
    """A study with a filled two-run sheet beside it, and the sheet's text."""
    base = Path(tmp) / "sbase"
    base.mkdir()
    for args in (
        ["synth", "--truth", TRUTH, "--seed", "3", "--nominal-inputs", "-o", "lab.toml"],
        ["init", "--data", "lab.toml", "--quiet"],
        ["plan", "--runs", "2", "--tubes-mm", "25,35,50", "-o", "plan.csv", "--quiet"],
        ["sim", "--plan", "plan.csv", "--truth", TRUTH, "-o", "lab", "--quiet"],
    ):
        rc, _, err = run(args, cwd=base)
        assert rc == 0, (args, err)
    return base, (base / "lab" / "plan-filled.csv").read_text()


def edit_cell(text, column, value, row=1):
    lines = text.splitlines(keepends=False)
    head = next(i for i, l in enumerate(lines) if not l.startswith("#"))
    cols = lines[head].split(",")
    k = cols.index(column)
    cells = lines[head + row].split(",")
    cells[k] = f'"{value}"' if "," in value else value
    lines[head + row] = ",".join(cells)
    return "\n".join(lines) + "\n"


def structural(text):
    lines = text.splitlines()
    head = next(i for i, l in enumerate(lines) if not l.startswith("#"))
    body = lines[head + 1:]
    yield "empty file", ""
    yield "header only", "\n".join(lines[: head + 1]) + "\n"
    yield "a column dropped", "\n".join(",".join(l.split(",")[1:]) for l in lines[head:]) + "\n"
    yield "two rows of one id", "\n".join(lines[: head + 1] + [body[0], body[0]]) + "\n"
    yield "a short row", "\n".join(lines[: head + 1] + [body[0][:40]]) + "\n"
    yield "a long row", "\n".join(lines[: head + 1] + [body[0] + ",1,2,3"]) + "\n"
    yield "a BOM", "\ufeff" + text
    yield "CRLF", text.replace("\n", "\r\n")
    yield "a header repeated", "\n".join(lines[: head + 1] + [lines[head]] + body) + "\n"
    yield "binary", "\x00\x01\x02garbage\xff"
    yield "100 000 rows", "\n".join(lines[: head + 1] + [body[0].replace("plan-1", f"r{i}", 1) for i in range(100000)]) + "\n"


def try_add(cat, name, d, sheet_text=None, path="sheet.csv", names=()):
    if sheet_text is not None:
        Path(d, path).write_text(sheet_text, encoding="utf-8", errors="surrogateescape")
    before = snapshot(d)
    res = run(["data", "add", path, "--no-diagnose", "--quiet"], cwd=d, timeout=300)

    def still_opens(_out):
        rc, out, err = run(["steps"], cwd=d)
        return None if rc == 0 else f"the study no longer opens: {err.strip()[-200:]}"

    why = judge(cat, name, res, names=names, before=before, folder=d, check=still_opens)
    return res[0], why


def attack_sheets(tmp):
    base, filled = loop_base(tmp)
    n = 0

    def fresh():
        nonlocal n
        n += 1
        d = Path(tmp) / f"s{n}"
        shutil.copytree(base, d)
        return d

    for col in COLUMNS:
        # An id is text: "nan" there is a name, which is printed as given.
        for v in [h for h in HOSTILE if col != "id" or h.strip("-") not in ("nan", "inf")]:
            d = fresh()
            try_add("sheet cells", f"{col} = {v[:20]!r}", d, edit_cell(filled, col, v), names=("sheet.csv",))
            shutil.rmtree(d)
    for name, text in structural(filled):
        d = fresh()
        try_add("sheet structure", name, d, text, names=("sheet.csv",))
        shutil.rmtree(d)
    d = fresh()
    os.mkfifo(d / "fifo.csv")
    for name, path in [
        ("the study itself", "swimbot-study.toml"), ("the dataset", "lab.toml"), ("/dev/null", "/dev/null"),
        ("/dev/zero", "/dev/zero"), ("a folder", "lab"), ("missing", "nope.csv"), ("a FIFO", "fifo.csv"),
        ("the unfilled plan", "plan.csv"),
    ]:
        try_add("sheet paths", name, d, None, path=path)
    # The same bytes under another name: refused as joined already.
    d2 = fresh()
    shutil.copy(d2 / "lab" / "plan-filled.csv", d2 / "copy.csv")
    assert run(["data", "add", "lab/plan-filled.csv", "--no-diagnose", "--quiet"], cwd=d2)[0] == 0
    try_add("sheet paths", "the same runs under another name", d2, None, path="copy.csv", names=("already joined",))
    # The same runs edited (another trial count): refused on their ids.
    Path(d2, "again.csv").write_text(edit_cell(filled, "trials", "6").replace("\n", "\n", 1))
    try_add("sheet paths", "the same runs, one cell changed", d2, None, path="again.csv", names=("id",))
    # sim --plan: hostile sheets and flags.
    d3 = fresh()
    for col in ["labels.set_point_hz", "frequency_hz", "channel_diameter_mm", "viscosity_pa_s", "labels.duration_s"]:
        for v in ["nan", "-1", "0", "1e308", "abc", "50"]:
            Path(d3, "bad.csv").write_text(edit_cell(filled, col, v))
            before = snapshot(d3)
            res = run(["sim", "--plan", "bad.csv", "--truth", TRUTH, "-o", "out", "--quiet"], cwd=d3, timeout=300)
            judge("sim --plan", f"{col} = {v}", res, before=before, folder=d3)
            shutil.rmtree(d3 / "out", ignore_errors=True)
    for flags in (["--noise", "nan"], ["--noise", "-0.1"], ["--noise", "2"], ["--trials", "1"], ["--trials", "0"],
                  ["--trials", "100000"], ["--seed", "-1"], ["--truth", ""], ["--truth", "base + nope"],
                  ["--truth", "base ++ backflow"], ["--max-time-s", "0"], ["--max-time-s", "nan"]):
        args = ["sim", "--plan", "plan.csv", "--truth", TRUTH, "-o", "out", "--quiet"]
        for i in range(0, len(flags), 2):
            if flags[i] in args:
                args[args.index(flags[i]) + 1] = flags[i + 1]
            else:
                args += flags[i:i + 2]
        before = snapshot(d3)
        judge("sim --plan", " ".join(flags), run(args, cwd=d3), before=before, folder=d3)
        shutil.rmtree(d3 / "out", ignore_errors=True)
