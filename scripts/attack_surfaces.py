#!/usr/bin/env python3
"""A scripted attack on the surfaces a lab feeds swimbot: the study file
(swimbot-study.toml), spreadsheets as labs export them (CSV with European
separators and decimal marks), and the Python package; and on the
answer-first commands (attack_screens.py: hostile datasets through
`diagnose`, `init`, `add`, `steps`, `undo`, `plan`, `report`, and terminal
widths; attack_outputs.py: where they write, what reaches `steps --format
latex|markdown`, `plan`'s flags; attack_pystudy.py: the Python `Study` API
and `Dataset.from_pandas`).

Every attempt is judged by the same rules: the run ends with exit 0 and no
NaN/inf printed, or exit 2 with a `swimbot: error:` message that names the
file (and the field where there is one); never a panic, a signal, a hang
or a silent wrong number; a refused command leaves every file it was given
byte for byte as it was, and no temporary file behind.

    SWIMBOT_BIN=target/release/swimbot python3 scripts/attack_surfaces.py [study|csv|python|hostile|names|widths|outputs|tables|plan|pystudy ...]

The Python parts need `import swimbot` (pip install ./python). The full
disk of `study` is simulated by debug builds only: run that part with
SWIMBOT_BIN=$PWD/target/debug/swimbot (a release binary writes the file,
and those attempts are tallied as faults). The tally is
printed at the end, one line per category: tried / faults; each fault is
printed with what was tried and what happened.
"""

import json
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from attack_common import BIN, FAULTS, PAPER_CSV, ROOT, TALLY, judge, record, run, snapshot  # noqa: F401


# --- the study file --------------------------------------------------------


def study_base(tmp):
    """A study on the paper's CSV with one step, made once and copied."""
    base = Path(tmp) / "base"
    base.mkdir()
    shutil.copy(PAPER_CSV, base / "paper.csv")
    rc, _, err = run(["init", "--data", "paper.csv"], cwd=base)
    assert rc == 0, err
    rc, _, err = run(["add", "body-correction", "--force"], cwd=base)
    assert rc == 0, err
    return base


def fresh(base, tmp, name):
    d = Path(tmp) / name
    shutil.copytree(base, d)
    return d


def study_mutants(text):
    """(name, new text) of hand edits a user might make or a crash leave."""
    rnd = random.Random(7)
    lines = text.splitlines(keepends=True)
    out = []
    n = len(text.encode())
    for k in range(40):
        cut = n * k // 40
        out.append((f"truncated at byte {cut}", text.encode()[:cut].decode("utf-8", "ignore")))
    for i in rnd.sample(range(len(lines)), min(40, len(lines))):
        out.append((f"line {i + 1} deleted", "".join(lines[:i] + lines[i + 1:])))
    numeric = [i for i, l in enumerate(lines) if re.match(r"^\s*[\w.]+ = -?[0-9]", l)]
    for i in rnd.sample(numeric, min(30, len(numeric))):
        for bad in ["nan", "inf", "-1e308", '"text"', "true", "1e999"]:
            key = lines[i].split("=")[0]
            out.append((f"line {i + 1} {key.strip()} = {bad}",
                        "".join(lines[:i] + [f"{key}= {bad}\n"] + lines[i + 1:])))
    for s in ["0", "2", "-1", "99999999999999999999", '"1"', "1.0"]:
        out.append((f"schema = {s}", re.sub(r"(?m)^schema = .*$", f"schema = {s}", text)))
    out.append(("schema removed", re.sub(r"(?m)^schema = .*\n", "", text)))
    out.append(("unknown field", text + "\nfavourite_colour = \"blue\"\n"))
    out.append(("empty", ""))
    out.append(("binary", "\x00\x01\x02" * 100))
    out.append(("a dataset, not a study", PAPER_CSV.read_text()))
    steps = text.split("[[steps]]")
    if len(steps) >= 2:
        out.append(("step duplicated", text + "\n[[steps]]" + steps[1]))
        out.append(("steps removed, diagnosis kept", steps[0]))
    out.append(("preset edited", re.sub(r'preset = "base"', 'preset = "nope"', text)))
    out.append(("likelihood edited", re.sub(r'likelihood = "\w+"', 'likelihood = "cauchy"', text)))
    out.append(("effect renamed", re.sub(r'name = "body-correction"', 'name = "no-such-effect"', text, count=1)))
    out.append(("dataset path absent", re.sub(r'(?m)^path = .*\n', "", text, count=1)))
    out.append(("sha256 edited", re.sub(r'sha256 = "[0-9a-f]{4}', 'sha256 = "0000', text, count=1)))
    return out


def attack_study(tmp):
    cat = "study file: hand edits and truncations"
    base = study_base(tmp)
    text = (base / "swimbot-study.toml").read_text()
    for k, (name, mutant) in enumerate(study_mutants(text)):
        d = fresh(base, tmp, f"m{k}")
        (d / "swimbot-study.toml").write_text(mutant)
        before = snapshot(d)
        for cmd in (["steps", "--format", "json"], ["compare", "--no-report", "--format", "json"]):
            judge(cat, f"{name}: {cmd[0]}", run(cmd, cwd=d), names=("swimbot-study.toml",),
                  before=before, folder=d)

    cat = "study file: what it points at"
    targets = {
        "missing dataset": lambda d: (d / "paper.csv").unlink(),
        "dataset is a folder": lambda d: ((d / "paper.csv").unlink(), (d / "paper.csv").mkdir()),
        "dataset changed by one byte": lambda d: (d / "paper.csv").write_text(
            (d / "paper.csv").read_text().replace("0.586", "0.587")),
        "dataset emptied": lambda d: (d / "paper.csv").write_text(""),
        "dataset 70 MB": lambda d: (d / "paper.csv").write_bytes(b"#" * (70 << 20)),
        "dataset -> /dev/zero": lambda d: ((d / "paper.csv").unlink(), (d / "paper.csv").symlink_to("/dev/zero")),
        "dataset a FIFO with no writer": lambda d: ((d / "paper.csv").unlink(), os.mkfifo(d / "paper.csv")),
        "dataset symlink loop": lambda d: ((d / "paper.csv").unlink(), (d / "paper.csv").symlink_to("paper.csv")),
        "study 200 MB": lambda d: (d / "swimbot-study.toml").write_bytes(
            (d / "swimbot-study.toml").read_bytes() + b"#" * (200 << 20)),
        "study -> /dev/zero": lambda d: ((d / "swimbot-study.toml").unlink(),
                                         (d / "swimbot-study.toml").symlink_to("/dev/zero")),
        "study a FIFO with no writer": lambda d: ((d / "swimbot-study.toml").unlink(),
                                                  os.mkfifo(d / "swimbot-study.toml")),
        "study a folder": lambda d: ((d / "swimbot-study.toml").unlink(), (d / "swimbot-study.toml").mkdir()),
    }
    for name, make in targets.items():
        d = fresh(base, tmp, "t-" + re.sub(r"\W", "_", name))
        make(d)
        before = snapshot(d)
        for cmd in (["steps"], ["add", "tail-confinement"], ["undo"], ["compare", "--no-report"]):
            judge(cat, f"{name}: {cmd[0]}", run(cmd, cwd=d, timeout=60), names=("swimbot-study.toml",),
                  before=before, folder=d)

    cat = "study file: steps out of order, concurrent adds"
    d = fresh(base, tmp, "order")
    rc, _, err = run(["add", "tail-confinement", "--force"], cwd=d)
    t = (d / "swimbot-study.toml").read_text()
    head, *steps = t.split("[[steps]]")
    if len(steps) == 2:
        (d / "swimbot-study.toml").write_text(head + "[[steps]]" + steps[1] + "[[steps]]" + steps[0])
        before = snapshot(d)
        for cmd in (["steps", "--format", "json"], ["undo"], ["add", "buoyancy"]):
            judge(cat, f"two steps swapped: {cmd[0]}", run(cmd, cwd=d), names=("swimbot-study.toml",),
                  before=before, folder=d)
    for trial in range(int(os.environ.get("ATTACK_CONCURRENT", "4"))):
        d = fresh(base, tmp, f"conc{trial}")
        effects = ["tail-confinement", "buoyancy", "wall-drag-body", "end-effects"][: 2 + trial % 3]
        procs = [subprocess.Popen([BIN, "add", e, "--force"], cwd=d, stdout=subprocess.PIPE,
                                  stderr=subprocess.PIPE, text=True) for e in effects]
        outs = [(p.wait(timeout=600), p.stdout.read(), p.stderr.read()) for p in procs]
        ok = sum(1 for rc, _, _ in outs if rc == 0)
        rc, out, err = run(["steps", "--format", "json"], cwd=d)
        n_steps = len(json.loads(out).get("step", [])) if rc == 0 else -1
        # Each add that said it succeeded must be in the study: one step
        # before, plus one per success.
        lost = n_steps != 1 + ok
        TALLY.setdefault(cat, [0, 0])
        TALLY[cat][0] += 1
        bad_rc = [o for o in outs if o[0] not in (0, 2) or "panicked" in o[2]]
        if lost or bad_rc:
            TALLY[cat][1] += 1
            FAULTS.append((cat, f"{len(effects)} concurrent adds", f"{ok} succeeded, study has {n_steps} steps"
                           + (f"; {bad_rc[0][0]}: {bad_rc[0][2][-200:]}" if bad_rc else ""), "", ""))

    cat = "study file: unwritable folder, full disk"
    for name, cmd, env in [
        ("add in a read-only folder (as nobody)", ["add", "tail-confinement"], None),
        ("undo in a read-only folder (as nobody)", ["undo"], None),
        ("init over it in a read-only folder (as nobody)", ["init", "--force", "--data", "paper.csv"], None),
        ("add on a full disk", ["add", "tail-confinement", "--force"], {"SWIMBOT_FAULT_DISK_FULL_AFTER_BYTES": "100"}),
        ("undo on a full disk", ["undo"], {"SWIMBOT_FAULT_DISK_FULL_AFTER_BYTES": "100"}),
        ("init on a full disk", ["init", "--force", "--data", "paper.csv"], {"SWIMBOT_FAULT_DISK_FULL_AFTER_BYTES": "100"}),
    ]:
        d = fresh(base, tmp, "w-" + re.sub(r"\W", "_", name))
        before = snapshot(d)
        if "nobody" in name:
            os.chmod(d, 0o555)
            os.chmod(tmp, 0o755)
            r = subprocess.run(["setpriv", "--reuid=65534", "--regid=65534", "--clear-groups", BIN, *cmd],
                               cwd=d, capture_output=True, text=True, timeout=300)
            res = (r.returncode, r.stdout, r.stderr)
            os.chmod(d, 0o755)
        else:
            res = run(cmd, cwd=d, env=env, timeout=300)
        judge(cat, name, res, names=("swimbot-study.toml",), before=before, folder=d, accept_ok=False)


# --- spreadsheets ------------------------------------------------------------


def paper_rows():
    head, rows = [], []
    for line in PAPER_CSV.read_text().splitlines():
        (head if line.startswith("#") else rows).append(line)
    return head, [r.split(",") for r in rows]


def sheet(head, rows, sep=",", dec=".", bom=False, eol="\n", quote="none", sep_line=False):
    def cell(c):
        try:
            float(c)
            num = True
        except ValueError:
            num = False
        if num and dec == ",":
            c = c.replace(".", ",")
        if quote == "all" or (quote == "numbers" and num) or (sep in c):
            c = '"' + c + '"'
        return c

    lines = (["sep=" + sep] if sep_line else []) + head + [sep.join(cell(c) for c in r) for r in rows]
    return ("\ufeff" if bom else "") + eol.join(lines) + eol


def reference_json():
    rc, out, err = run(["compare", "--no-report", "--format", "json", "--data", str(PAPER_CSV)])
    assert rc == 0, err
    d = json.loads(out)
    d.pop("swimbot", None)
    return d


def same_as(ref):
    def check(out):
        d = json.loads(out)
        d.pop("swimbot", None)
        d.get("data", {}).pop("file", None) if isinstance(d.get("data"), dict) else None
        a = [(c["id"], c.get("u_pred_mm_s"), c.get("u_meas_mm_s")) for c in d["cases"]]
        b = [(c["id"], c.get("u_pred_mm_s"), c.get("u_meas_mm_s")) for c in ref["cases"]]
        return None if a == b else f"different numbers: {a[0]} vs {b[0]}"
    return check


def attack_csv(tmp):
    ref = reference_json()
    head, rows = paper_rows()
    tmp = Path(tmp)
    cat = "CSV: European dialects (must equal the paper's numbers)"
    k = 0
    for sep in [",", ";", "\t"]:
        for dec in [".", ","]:
            for bom in [False, True]:
                for eol in ["\n", "\r\n"]:
                    for quote in ["none", "all", "numbers"]:
                        for sep_line in [False, True]:
                            name = f"sep={sep!r} dec={dec!r} bom={bom} eol={eol!r} quote={quote} sep_line={sep_line}"
                            f = tmp / f"eu{k}.csv"
                            k += 1
                            f.write_text(sheet(head, rows, sep, dec, bom, eol, quote, sep_line), newline="")
                            judge(cat, name, run(["compare", "--no-report", "--format", "json", "--data", str(f)]),
                                  names=(f.name,), check=same_as(ref))
    cat = "CSV: broken or odd sheets (refused naming file, row and field, or read right)"
    eu = sheet(head, rows, ";", ",", True, "\r\n")
    lines = eu.split("\r\n")
    data_at = len(head) + 0
    cases = {
        "empty lines between rows": "\r\n".join(lines[: data_at + 2] + ["", ""] + lines[data_at + 2:]),
        "lines of only separators": "\r\n".join(lines[: data_at + 2] + [";;;;;;;;"] + lines[data_at + 2:]),
        "trailing separator on every row": "\r\n".join(l + ";" if l and not l.startswith("#") and not l.startswith("\ufeff#") else l for l in lines),
        "one row with commas, the rest semicolons": "\r\n".join(
            lines[: data_at + 2] + [sheet([], [rows[1]], ",", ".").strip()] + lines[data_at + 3:]),
        "one row with tabs": "\r\n".join(lines[: data_at + 2] + [lines[data_at + 2].replace(";", "\t")] + lines[data_at + 3:]),
        "decimal point in one cell of a comma sheet": eu.replace("0,586", "0.586"),
        "thousands separator 1.234,5 in a length": eu.replace(";130;", ";1.130,0;"),
        "thousands separator without decimals 1.130": eu.replace(";130;", ";1.130;"),
        "space thousands 1 130": eu.replace(";130;", ";1 130;"),
        "no-break-space thousands": eu.replace(";130;", ";1\u00a0130;"),
        "percent cell": eu.replace("0,586", "58,6%"),
        "exponent with decimal comma 5,86E-1": eu.replace("0,586", "5,86E-1"),
        "unbalanced quote": eu.replace("0,586", '"0,586'),
        "quoted cell with a newline": eu.replace("0,586", '"0,\n586"'),
        "NUL byte in a cell": eu.replace("0,586", "0,5\x0086"),
        "cell of 10^6 characters": eu.replace("0,586", "9" * 1_000_000),
        "id of 10^5 characters": eu.replace("tail-1", "t" * 100_000),
        "header only": "\r\n".join(lines[: data_at + 1]),
        "BOM twice": "\ufeff" + eu,
        "CR only line ends": eu.replace("\r\n", "\r"),
        "header repeated as a row": "\r\n".join(lines[: data_at + 1] + [lines[data_at]] + lines[data_at + 1:]),
        "duplicate column": eu.replace("tail_length_mm;", "tail_length_mm;tail_length_mm;", 1).replace(";130;", ";130;130;"),
        "column names in another case": eu.replace("wavelength_mm", "Wavelength_MM"),
        "column name with a unit in brackets": eu.replace("wavelength_mm", "wavelength [mm]"),
        "minus sign U+2212": eu.replace("0,586", "\u22120,586"),
        "comma decimal in the # setup": eu.replace("# viscosity_pa_s = 3.5", "# viscosity_pa_s = 3,5"),
        "semicolons in the # setup": eu.replace("# viscosity_pa_s = 3.5", "# viscosity_pa_s = 3.5;;;;;"),
    }
    # What a lab's sheet means and must be read as: the paper's numbers.
    same = {"empty lines between rows", "lines of only separators", "trailing separator on every row",
            "comma decimal in the # setup", "semicolons in the # setup", "CR only line ends"}
    for name, text in cases.items():
        f = tmp / f"odd-{re.sub(r'[^a-z0-9]+', '-', name.lower())}.csv"
        f.write_text(text, newline="", encoding="utf-8", errors="surrogatepass")
        if name in same:
            judge(cat, name, run(["compare", "--no-report", "--format", "json", "--data", str(f)]),
                  names=(f.name,), check=same_as(ref))
        else:
            judge(cat, name, run(["convert", str(f), "--to", "toml"]), names=(f.name,))
    # Read as meant, or refused naming the file: never another number.
    def extra(names, cells):
        return sheet(head, [rows[0] + names] + [r + cells for r in rows[1:]], ";", ",", True, "\r\n")

    meant = {
        "thousands 1.013,25 in a recorded column": (extra(["pressure_hpa"], ["1.013,25"]), 1013.25),
        "thousands 1 013,25 (no-break space)": (extra(["pressure_hpa"], ["1\u00a0013,25"]), 1013.25),
        "short lab column names T, pH": (extra(["T", "pH"], ["21,5", "7"]), 7.0),
    }
    for name, (text, want) in meant.items():
        f = tmp / f"meant-{re.sub(r'[^a-z0-9]+', '-', name.lower())}.csv"
        f.write_text(text, newline="", encoding="utf-8")
        res = run(["convert", str(f), "--to", "toml"])
        judge(cat, name, res, names=(f.name,), accept_ok=True,
              check=lambda out, w=want: None if re.search(rf"= {w}\b", out) else f"{w} not read")
        if res[0] == 2:
            TALLY[cat][1] += 1
            FAULTS.append((cat, name, "a lab's sheet refused", "2", res[2][-200:]))
    cat = "CSV: encodings and sizes"
    sizes = {
        "UTF-16LE export (Excel 'Unicode text')": lambda f: f.write_bytes(
            b"\xff\xfe" + sheet(head, rows, "\t", ",").encode("utf-16-le")),
        "Latin-1 export with a degree sign": lambda f: f.write_bytes(
            sheet(head + ["# note = \"20 \u00b0C\""], rows, ";", ",").encode("latin-1")),
        "10^6 columns": lambda f: f.write_text(
            "\n".join(head) + "\n" + ",".join(["id"] + [f"c{i}" for i in range(10 ** 6)]) + "\n"),
        "10^6 extra numeric cells in one row": lambda f: f.write_text(
            "\n".join(head) + "\n" + ",".join(rows[0]) + "\n" + ",".join(rows[1] + ["1"] * 10 ** 6) + "\n"),
        "10^5 rows of separators": lambda f: f.write_text(
            "\n".join(head) + "\n" + ",".join(rows[0]) + "\n" + ",".join(rows[1]) + "\n" + ";;;;\n" * 100_000),
        "one line of 60 MB": lambda f: f.write_text("\n".join(head) + "\n" + ",".join(rows[0]) + "\n" + "x" * (60 << 20)),
    }
    for name, make in sizes.items():
        f = tmp / f"big-{re.sub(r'[^a-z0-9]+', '-', name.lower())}.csv"
        make(f)
        t0 = time.perf_counter()
        res = run(["convert", str(f), "--to", "toml"], timeout=60)
        took = time.perf_counter() - t0
        why = judge(cat, name, res, names=(f.name,))
        if why is None and took > 10:
            TALLY[cat][1] += 1
            FAULTS.append((cat, name, f"took {took:.1f} s", str(res[0]), ""))
        f.unlink()


# --- the Python package ------------------------------------------------------


def attack_python(tmp):
    import numpy as np

    import swimbot

    cat = "Python: bad arguments (SwimbotError naming the argument, no crash)"
    TALLY.setdefault(cat, [0, 0])

    def expect_error(name, f, must=()):
        TALLY[cat][0] += 1
        try:
            r = f()
        except swimbot.SwimbotError as e:
            miss = [m for m in must if m not in str(e)]
            if miss:
                TALLY[cat][1] += 1
                FAULTS.append((cat, name, f"message does not name {miss}", "", str(e)[:300]))
            return
        except MemoryError:
            TALLY[cat][1] += 1
            FAULTS.append((cat, name, "MemoryError (allocated before refusing)", "", ""))
            return
        except Exception as e:  # noqa: BLE001
            TALLY[cat][1] += 1
            FAULTS.append((cat, name, f"{type(e).__name__} instead of SwimbotError", "", str(e)[:300]))
            return
        vals = [np.asarray(x) for x in (r if isinstance(r, tuple) else ())]
        if any(v.dtype.kind == "f" and not np.isfinite(v).all() for v in vals):
            why = "non-finite numbers returned"
        else:
            why = "accepted"
        TALLY[cat][1] += 1
        FAULTS.append((cat, name, why, "", ""))

    S = swimbot.sweep
    for bad, label in [(np.nan, "NaN"), (np.inf, "inf"), (-np.inf, "-inf"), (-1.0, "negative"), (0.0, "zero"),
                       (1e300, "1e300"), (np.array([12.0, np.nan]), "array with a NaN")]:
        for field in ["wavelength_mm", "amplitude_mm", "tail_length_mm", "frequency_hz"]:
            expect_error(f"sweep {field}={label}", lambda: S(**{field: bad}), must=(field,))
    for bad, label in [("12", "a string"), (np.array(["a", "b"]), "string array"), (1 + 2j, "complex"),
                       (np.array([1 + 1j]), "complex array"), (object(), "an object"), ([[1, 2], [3]], "ragged list"),
                       (None if False else {"a": 1}, "a dict"), (np.array([12, 13], dtype=object), "object array")]:
        expect_error(f"sweep wavelength_mm={label}", lambda: S(wavelength_mm=bad), must=("wavelength_mm",))
    expect_error("sweep 10^10 geometries by broadcast", lambda: S(wavelength_mm=np.linspace(8, 16, 100000)[:, None],
                                                                     amplitude_mm=np.linspace(1, 7, 100000)[None, :]),
                 must=("geometries",))
    expect_error("sweep shapes that do not broadcast", lambda: S(wavelength_mm=np.ones(3) * 12, amplitude_mm=np.ones(4) * 2))
    expect_error("sweep unknown case", lambda: S(wavelength_mm=12.0, case="nope"), must=("nope",))
    expect_error("sweep unknown preset", lambda: S(wavelength_mm=12.0, preset="nope"), must=("nope",))
    expect_error("sweep unknown effect", lambda: S(wavelength_mm=12.0, effects=["nope"]), must=("nope",))
    expect_error("sweep data of the wrong type", lambda: S(wavelength_mm=12.0, data="paper.csv"))
    expect_error("sweep wavelength below twice the wire", lambda: S(wavelength_mm=1.5), must=("wavelength",))
    expect_error("compare with a string for ds that is no file", lambda: swimbot.compare("no-such.csv"), must=("no-such.csv",))
    expect_error("compare mc_draws=-1", lambda: swimbot.compare(mc_draws=-1), must=("mc-draws",))
    expect_error("compare effects=[None]", lambda: swimbot.compare(effects=[None]))
    expect_error("compare effects=5", lambda: swimbot.compare(effects=5))
    expect_error("compare ds=42", lambda: swimbot.compare(42))
    expect_error("fit with no effect", lambda: swimbot.fit(effects=[]))
    expect_error("audit family_samples=3", lambda: swimbot.audit(family_samples=3), must=("family-samples",))
    expect_error("load a folder", lambda: swimbot.load(tmp), must=(str(tmp),))
    expect_error("load /dev/zero", lambda: swimbot.load("/dev/zero"), must=("/dev/zero",))

    import pandas as pd

    df = pd.read_csv(PAPER_CSV, comment="#")
    setup = {"wire_diameter_mm": 1.0, "channel_diameter_mm": 35.0, "channel_length_mm": 350.0,
             "viscosity_pa_s": 3.5, "density_kg_m3": 985.0, "body_diameter_mm": 20.0, "body_length_mm": 50.0,
             "coupler_diameter_mm": 6.0, "coupler_length_mm": 10.0, "trials": 5}
    F = swimbot.Dataset.from_pandas
    expect_error("from_pandas without wavelength_mm", lambda: F(df.drop(columns=["wavelength_mm"]), setup=setup),
                 must=("wavelength_mm",))
    # Without ids the format numbers the cases (#1, #2, ...): accepted, as the CLI does.
    TALLY[cat][0] += 1
    try:
        if len(F(df.drop(columns=["id"]), setup=setup)) != 6:
            TALLY[cat][1] += 1
            FAULTS.append((cat, "from_pandas without id", "not 6 cases", "", ""))
    except Exception as e:  # noqa: BLE001
        TALLY[cat][1] += 1
        FAULTS.append((cat, "from_pandas without id", f"refused: {e}", "", ""))
    expect_error("from_pandas empty frame", lambda: F(df.iloc[0:0], setup=setup))
    expect_error("from_pandas no columns", lambda: F(pd.DataFrame(), setup=setup))
    expect_error("from_pandas NaN wavelength", lambda: F(df.assign(wavelength_mm=np.nan), setup=setup),
                 must=("wavelength_mm",))
    expect_error("from_pandas inf speed", lambda: F(df.assign(u_mm_s=np.inf), setup=setup), must=("u_mm_s",))
    expect_error("from_pandas wavelength as text", lambda: F(df.assign(wavelength_mm="long"), setup=setup),
                 must=("wavelength_mm",))
    expect_error("from_pandas setup NaN", lambda: F(df, setup={**setup, "viscosity_pa_s": float("nan")}),
                 must=("viscosity_pa_s",))
    expect_error("from_pandas setup unknown key", lambda: F(df, setup={**setup, "viscosty_pa_s": 3.5}),
                 must=("viscosty_pa_s",))
    expect_error("from_pandas setup object", lambda: F(df, setup={**setup, "viscosity_pa_s": object()}),
                 must=("viscosity_pa_s",))
    expect_error("from_pandas setup key with a newline", lambda: F(df, setup={**setup, "a\nb": 1}))
    # A name is one TOML string: a newline in it forges no setup line.
    TALLY[cat][0] += 1
    forged = F(df, setup=setup, name="x\n# viscosity_pa_s = 1e9")
    if forged.name != "x\n# viscosity_pa_s = 1e9" or swimbot.compare(forged).mare != swimbot.compare(F(df, setup=setup)).mare:
        TALLY[cat][1] += 1
        FAULTS.append((cat, "from_pandas name with a newline", "the name changed the data", "", ""))
    expect_error("from_pandas duplicate ids, different geometry",
                 lambda: F(df.assign(id="same"), setup=setup), must=("same",))
    expect_error("from_pandas 10^4+1 rows", lambda: F(pd.concat([df] * 1700, ignore_index=True).assign(
        id=[f"c{i}" for i in range(6 * 1700)]), setup=setup), must=("10000",))

    cat = "Python: the same call gives the same result, whatever came before"
    TALLY.setdefault(cat, [0, 0])
    first = swimbot.compare().to_dict()
    fd = swimbot.diagnose(pairs=False, discovery=False).to_dict()
    u0, _ = S(wavelength_mm=np.linspace(8, 16, 50), amplitude_mm=2.5)
    eff_a = Path(tmp) / "a.toml"
    eff_b = Path(tmp) / "b.toml"
    law = '[[effect]]\nname = "{n}"\nstatement = "a test law"\nreference = "none"\ntarget = "tail_drag"\nformula = "{f}"\n'
    eff_a.write_text(law.format(n="mine", f="1 + 0.1"))
    eff_b.write_text(law.format(n="mine", f="1 + 0.5"))
    for i in range(60):
        try:
            kind = i % 6
            if kind == 0:
                swimbot.compare(effects=["tail-confinement"])
            elif kind == 1:
                swimbot.compare(effect_files=[eff_a if i % 12 < 6 else eff_b], effects=["mine"])
            elif kind == 2:
                swimbot.sweep(wavelength_mm=np.nan)
            elif kind == 3:
                swimbot.diagnose(pairs=False, discovery=False, effects=["buoyancy"])
            elif kind == 4:
                swimbot.load(PAPER_CSV)
            else:
                swimbot.fit(effects=["tail-confinement"])
        except swimbot.SwimbotError:
            pass
        TALLY[cat][0] += 1
        now = swimbot.compare().to_dict()
        u1, _ = S(wavelength_mm=np.linspace(8, 16, 50), amplitude_mm=2.5)
        bad = now != first or not np.array_equal(u0, u1)
        if i % 10 == 9:
            bad = bad or swimbot.diagnose(pairs=False, discovery=False).to_dict() != fd
        if bad:
            TALLY[cat][1] += 1
            FAULTS.append((cat, f"after call {i} (kind {kind})", "result changed", "", ""))
    # Two files defining one name: the second call must see the second file.
    TALLY[cat][0] += 1
    try:
        a = swimbot.compare(effect_files=[eff_a], effects=["mine"]).mare
        b = swimbot.compare(effect_files=[eff_b], effects=["mine"]).mare
        a2 = swimbot.compare(effect_files=[eff_a], effects=["mine"]).mare
        if a == b or a != a2:
            TALLY[cat][1] += 1
            FAULTS.append((cat, "one effect name in two files, called in turn", f"MARE {a} {b} {a2}", "", ""))
    except swimbot.SwimbotError as e:
        if "mine" not in str(e):
            TALLY[cat][1] += 1
            FAULTS.append((cat, "one effect name in two files", "refused without naming it", "", str(e)[:200]))


def main():
    from attack_outputs import attack_outputs, attack_plan_flags, attack_tables
    from attack_pystudy import attack_study_api
    from attack_sheets import attack_sheets
    from attack_screens import attack_file_names, attack_hostile, attack_widths

    attacks = {"study": attack_study, "csv": attack_csv, "python": attack_python, "hostile": attack_hostile, "names": attack_file_names,
               "widths": attack_widths, "outputs": attack_outputs, "tables": attack_tables,
               "plan": attack_plan_flags, "pystudy": attack_study_api,
               "sheets": attack_sheets}
    which = sys.argv[1:] or list(attacks)
    with tempfile.TemporaryDirectory() as tmp:
        os.chmod(tmp, 0o755)
        for w in which:
            sub = Path(tmp) / w
            sub.mkdir()
            t0 = time.perf_counter()
            attacks[w](sub)
            print(f"# {w}: {time.perf_counter() - t0:.0f} s", file=sys.stderr)
    for cat, name, why, rc, err in FAULTS:
        print(f"FAULT [{cat}] {name}: {why} (exit {rc}) {err!r}")
    print()
    tried = sum(t for t, _ in TALLY.values())
    faults = sum(f for _, f in TALLY.values())
    for cat, (t, f) in TALLY.items():
        print(f"{t:5d} tried {f:4d} faults  {cat}")
    print(f"{tried:5d} tried {faults:4d} faults  in all")
    return 1 if faults else 0


if __name__ == "__main__":
    sys.exit(main())
