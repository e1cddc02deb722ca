"""The Python package against the CLI: the same numbers, the same messages.

The CLI binary is ``$SWIMBOT_BIN`` or the workspace's ``target/debug/swimbot``
(``scripts/test`` builds it before it runs this suite).
"""

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import swimbot

ROOT = Path(__file__).resolve().parents[2]
PAPER_CSV = ROOT / "host" / "data" / "paper.csv"
PAPER_TOML = ROOT / "host" / "data" / "paper.toml"


def cli_binary() -> str:
    path = os.environ.get("SWIMBOT_BIN") or str(ROOT / "target" / "debug" / "swimbot")
    assert Path(path).exists(), f"no swimbot binary at {path}: build it, or set SWIMBOT_BIN"
    return path


def cli_json(*args) -> dict:
    out = subprocess.run(
        [cli_binary(), *args, "--format", "json"], capture_output=True, text=True, check=True
    )
    doc = json.loads(out.stdout)
    doc.pop("swimbot")  # the provenance block
    return doc


def european(text: str) -> str:
    """The CSV as a decimal-comma spreadsheet saves it: `;`, commas in
    numbers, a BOM, CRLF (the `#` lines are text and kept)."""
    lines = []
    for line in text.splitlines():
        if line.startswith("#"):
            lines.append(line.replace(",", ";"))
            continue
        cells = []
        for c in line.split(","):
            try:
                float(c)
                cells.append(c.replace(".", ","))
            except ValueError:
                cells.append(c)
        lines.append(";".join(cells))
    return "\ufeff" + "\r\n".join(lines) + "\r\n"


def test_load_reads_csv_and_toml_alike():
    a, b = swimbot.load(PAPER_CSV), swimbot.load(PAPER_TOML)
    assert a.ids == b.ids == ["tail-1", "tail-2", "tail-3", "tail-4", "tail-5", "tail-6"]
    assert len(a) == 6 and a.note is None
    assert swimbot.compare(a).to_dict() == swimbot.compare(b).to_dict()


def test_compare_equals_the_cli_json():
    cmp = swimbot.compare(swimbot.load(PAPER_CSV))
    want = cli_json("compare", "--no-report", "--data", str(PAPER_CSV))
    assert cmp.to_dict() == want
    assert cmp.mare == want["summary"]["mare"]
    assert cmp.chi2_reduced == want["summary"]["chi2_reduced"]
    with_effect = swimbot.compare(effects=["tail-confinement"], preset="base")
    want = cli_json(
        "compare", "--no-report", "--preset", "base", "--effect", "tail-confinement"
    )
    assert with_effect.to_dict() == want
    assert with_effect.mare != cmp.mare


def test_a_european_export_gives_the_same_numbers(tmp_path):
    path = tmp_path / "paper-eu.csv"
    path.write_text(european(PAPER_CSV.read_text()), encoding="utf-8", newline="")
    with pytest.warns(UserWarning, match="decimal commas"):
        ds = swimbot.load(path)
    assert swimbot.compare(ds).to_dict() == swimbot.compare(swimbot.load(PAPER_CSV)).to_dict()


def test_diagnose_fit_and_audit_equal_the_cli_json():
    ds = swimbot.load(PAPER_CSV)
    d = swimbot.diagnose(ds, discovery=False)
    assert d.to_dict() == cli_json("diagnose", "--no-discovery", "--data", str(PAPER_CSV))
    assert d.trends and {"quantity", "feature_id", "r"} <= set(d.trends[0])
    f = swimbot.fit(ds, effects=["tail-confinement"])
    assert f.to_dict() == cli_json("fit", "--effect", "tail-confinement", "--data", str(PAPER_CSV))
    assert f.estimates[0]["name"] == "gamma"
    a = swimbot.audit(ds, family_samples=16)
    assert a.to_dict() == cli_json("audit", "--family-samples", "16", "--data", str(PAPER_CSV))


def test_results_show_as_tables_and_the_reports_figures():
    cmp = swimbot.compare()
    page = cmp._repr_html_()
    assert "<table>" in page and page.count("<svg") >= 2 and "tail-6" in page
    df = cmp.to_pandas()
    assert list(df["id"]) == swimbot.paper().ids
    assert df["u_pred_mm_s"].tolist() == [c["u_pred_mm_s"] for c in cmp.to_dict()["cases"]]


def test_from_pandas_with_a_setup_and_a_recorded_column():
    import pandas as pd

    rows = pd.read_csv(PAPER_CSV, comment="#")
    setup_lines = [
        l[2:] for l in PAPER_CSV.read_text().splitlines() if re.match(r"# [a-z0-9_.]+ = ", l)
    ]
    setup = {}
    for line in setup_lines:
        key, value = line.split(" = ", 1)
        if key in ("name", "source") or key.startswith("uncertainty.") or key == "body_profile":
            continue
        setup[key] = json.loads(value.lower()) if value not in ("true", "false") else value == "true"
    setup["body_profile"] = [[10.0, 20.0], [30.0, 18.0], [10.0, 20.0]]
    rows["temperature_c"] = [20.0, 21.0, 22.5, 23.0, 24.0, 25.5]
    with pytest.warns(UserWarning, match="temperature_c"):
        ds = swimbot.Dataset.from_pandas(rows, setup=setup, name="lab")
    cmp = swimbot.compare(ds)
    base = swimbot.compare(swimbot.load(PAPER_CSV))
    assert [c["u_pred_mm_s"] for c in cmp.to_dict()["cases"]] == [
        c["u_pred_mm_s"] for c in base.to_dict()["cases"]
    ]
    assert cmp.to_pandas()["temperature_c"].tolist() == rows["temperature_c"].tolist()
    trends = swimbot.diagnose(ds, discovery=False).trends
    assert any(t["feature_id"] == "temperature_c" for t in trends)


def test_sweep_broadcasts_and_equals_compare():
    ds = swimbot.paper()
    cmp = swimbot.compare(ds).to_dict()["cases"]
    toml = PAPER_CSV.read_text().splitlines()
    rows = [l.split(",") for l in toml if l.startswith("tail-")]
    lam, amp, length, f = (np.array([float(r[i]) for r in rows]) for i in (1, 2, 3, 4))
    u, omega = swimbot.sweep(lam, amp, length, f)
    assert u.tolist() == [c["u_pred_mm_s"] for c in cmp]
    assert omega.tolist() == [c["omega_pred_hz"] for c in cmp]
    u, omega = swimbot.sweep(np.linspace(8, 16, 5)[:, None], np.array([2.0, 2.5, 3.0]), 88.0)
    assert u.shape == omega.shape == (5, 3)
    assert np.all(np.isfinite(u)) and np.all(u > 0)


def test_errors_carry_the_clis_message(tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text(PAPER_CSV.read_text().replace("tail-3,16,", "tail-3,-16,"))
    with pytest.raises(swimbot.SwimbotError) as e:
        swimbot.load(bad)
    msg = str(e.value)
    for needle in ["bad.csv", "tail-3", "wavelength_mm", "positive"]:
        assert needle in msg
    with pytest.raises(swimbot.SwimbotError, match="no-such-effect"):
        swimbot.compare(effects=["no-such-effect"])
    with pytest.raises(swimbot.SwimbotError, match="geometry 1"):
        swimbot.sweep(wavelength_mm=[10.0, -1.0], amplitude_mm=2.5, tail_length_mm=88)
    assert issubclass(swimbot.SwimbotError, ValueError)


def test_repeated_calls_do_not_drift():
    first = swimbot.compare(effects=["tail-confinement"]).to_dict()
    for _ in range(3):
        swimbot.diagnose(discovery=False)
        assert swimbot.compare(effects=["tail-confinement"]).to_dict() == first


def test_pandas_is_optional_at_import():
    code = "import sys; sys.modules['pandas'] = None; import swimbot; print(swimbot.compare().mare)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert float(out.stdout) == swimbot.compare().mare


def test_sweep_refuses_what_numpy_would_bend_naming_the_argument():
    # A broadcast of 10^10 geometries is refused before 80 GB are made.
    big = (np.linspace(8, 16, 100_000)[:, None], np.linspace(1, 7, 100_000)[None, :])
    with pytest.raises(swimbot.SwimbotError, match="10000000000 geometries"):
        swimbot.sweep(*big)
    # numpy would read "12" as 12.0, None as NaN, drop an imaginary part.
    for bad in ["12", np.array(["a"]), 1 + 2j, np.array([12 + 1j]), {"a": 1}, [[1, 2], [3]], np.array([12.0], dtype=object), True]:
        with pytest.raises(swimbot.SwimbotError, match="wavelength_mm"):
            swimbot.sweep(wavelength_mm=bad)
    for bad in [np.nan, np.inf, -1.0, 0.0]:
        with pytest.raises(swimbot.SwimbotError, match="amplitude_mm"):
            swimbot.sweep(amplitude_mm=bad)
    with pytest.raises(swimbot.SwimbotError, match="broadcast"):
        swimbot.sweep(wavelength_mm=np.full(3, 12.0), amplitude_mm=np.full(4, 2.5))
    with pytest.raises(swimbot.SwimbotError, match="Dataset"):
        swimbot.sweep(wavelength_mm=12.0, data="paper.csv")
    u, omega = swimbot.sweep(wavelength_mm=np.empty((0, 3)))
    assert u.shape == omega.shape == (0, 3)
    # Integer arrays are numbers.
    assert swimbot.sweep(wavelength_mm=np.array([12]))[0][0] == swimbot.sweep(wavelength_mm=12.0)[0][()]


def test_from_pandas_refuses_setup_keys_that_would_forge_lines():
    import pandas as pd

    df = pd.read_csv(PAPER_CSV, comment="#")
    with pytest.raises(swimbot.SwimbotError, match="setup key"):
        swimbot.Dataset.from_pandas(df, setup={"a\nid,wavelength_mm": 1})
    with pytest.raises(swimbot.SwimbotError, match="viscosity_pa_s"):
        swimbot.Dataset.from_pandas(df, setup={"viscosity_pa_s": float("nan")})


def test_the_study_from_python_is_the_clis(tmp_path):
    data = tmp_path / "paper.csv"
    data.write_text(PAPER_CSV.read_text())
    path = tmp_path / "swimbot-study.toml"
    s = swimbot.Study.init(path, data, diagnose=False)
    step = s.add("buoyancy", force=True, diagnose=False)
    assert step["effect"]["name"] == "buoyancy"
    # What the CLI reads back is what Python wrote.
    out = subprocess.run(
        [cli_binary(), "--study", str(path), "steps", "--format", "json"], capture_output=True, text=True, check=True
    )
    doc = json.loads(out.stdout)
    assert doc["step"][0]["after"] == s.steps()["step"][0]["after"]
    # A second view of the study, opened before the first wrote, is refused.
    stale = swimbot.Study.open(path)
    s.add("backflow", force=True, diagnose=False)
    with pytest.raises(swimbot.SwimbotError, match="changed the study"):
        stale.undo()
    assert len(swimbot.Study.open(path).steps()["step"]) == 2
    page = s.report(tmp_path / "report")
    assert Path(page).name == "index.html" and Path(page).exists()
    applied = s.apply_to(swimbot.paper())
    assert len(applied["steps"]) == 2
    assert s.undo()["effect"]["name"] == "backflow"
    with pytest.raises(swimbot.SwimbotError, match="swimbot-study.toml"):
        swimbot.Study.init(path, data)
    with pytest.raises(swimbot.SwimbotError, match="no-such-effect"):
        s.add("no-such-effect")


def test_each_reports_inputs_are_its_own_studys_files(tmp_path):
    """Two studies in one interpreter: each report names the files its own
    study read, not what earlier calls read (a notebook makes many)."""
    import hashlib

    swimbot.load(PAPER_TOML)  # an earlier call's read
    listed = []
    for name, source in [("a.csv", PAPER_CSV), ("b.toml", PAPER_TOML)]:
        folder = tmp_path / name.split(".")[0]
        folder.mkdir()
        data = folder / name
        data.write_bytes(source.read_bytes())
        s = swimbot.Study.init(folder / "swimbot-study.toml", data, diagnose=False)
        page = Path(s.report(folder / "report"))
        manifest = json.loads((page.parent / "manifest.json").read_text())
        inputs = manifest["swimbot"]["inputs"]
        sha = hashlib.sha256(data.read_bytes()).hexdigest()
        listed.append([(Path(i["path"]).name, i["sha256"]) for i in inputs])
        assert listed[-1] == [(name, sha)], inputs
    assert listed[0] != listed[1]


def test_a_report_names_its_own_command_and_marks_its_folder(tmp_path):
    """A report written from Python records the command `swimbot report`
    would have been given (not the interpreter's argv) and marks its
    folder as the report's, as the command does: another command's output
    is refused there, a second report is not."""
    data = tmp_path / "paper.csv"
    data.write_bytes(PAPER_CSV.read_bytes())
    study = tmp_path / "swimbot-study.toml"
    s = swimbot.Study.init(study, data, diagnose=False)
    folder = tmp_path / "out" / "report"
    page = Path(s.report(folder))
    manifest = json.loads((page.parent / "manifest.json").read_text())
    assert manifest["swimbot"]["command"] == [
        "swimbot", "--study", str(study), "report", "-o", str(folder)
    ]
    marker = (folder / ".swimbot-output").read_text()
    assert marker.startswith("written by: swimbot report\n"), marker
    assert Path(s.report(folder)) == page
    r = subprocess.run(
        [cli_binary(), "compare", "--data", str(data), "-o", str(folder)],
        capture_output=True,
        text=True,
    )
    assert r.returncode == 2 and "swimbot report" in r.stderr, r.stderr


def test_bad_arguments_are_swimbot_errors_naming_them():
    # `-1` reaches the flag's own check (it read as another flag).
    with pytest.raises(swimbot.SwimbotError, match="mc-draws"):
        swimbot.compare(mc_draws=-1)
    for bad in [[None], 5, {"a": 1}, b"tail-confinement"]:
        with pytest.raises(swimbot.SwimbotError, match="effects"):
            swimbot.compare(effects=bad)
    with pytest.raises(swimbot.SwimbotError, match="cases"):
        swimbot.fit(effects=["tail-confinement"], cases=[3])
    import pandas as pd

    df = pd.read_csv(PAPER_CSV, comment="#")
    with pytest.raises(swimbot.SwimbotError, match="setup: viscosity_pa_s"):
        swimbot.Dataset.from_pandas(df, setup={"viscosity_pa_s": object()})


def test_a_study_call_given_a_wrong_type_is_refused_by_name_and_writes_nothing(tmp_path, monkeypatch):
    # `str(None)` was taken as a path: Study.init(None, ...) made a file
    # called `None`, report(42) a folder `42`.
    monkeypatch.chdir(tmp_path)
    data = tmp_path / "paper.csv"
    data.write_text(PAPER_CSV.read_text())
    s = swimbot.Study.init(tmp_path / "s.toml", data, diagnose=False)
    for bad in (None, 42, 3.5, True, ["s.toml"], ""):
        with pytest.raises(swimbot.SwimbotError, match="path"):
            swimbot.Study.init(bad, data, diagnose=False)
        with pytest.raises(swimbot.SwimbotError, match="path"):
            swimbot.Study.open(bad)
        with pytest.raises(swimbot.SwimbotError, match="directory"):
            s.report(bad)
        with pytest.raises(swimbot.SwimbotError, match="data"):
            swimbot.Study.init(tmp_path / "t.toml", bad, diagnose=False)
    # Types pyo3 refused with a TypeError, now the package's own error.
    with pytest.raises(swimbot.SwimbotError, match="preset"):
        swimbot.Study.init(tmp_path / "u.toml", data, preset=None, diagnose=False)
    with pytest.raises(swimbot.SwimbotError, match="likelihood"):
        swimbot.Study.init(tmp_path / "u.toml", data, likelihood=3, diagnose=False)
    with pytest.raises(swimbot.SwimbotError, match="refit_all"):
        s.add("buoyancy", refit_all=None)
    with pytest.raises(swimbot.SwimbotError, match="effect"):
        s.add(None)
    # apply_to(None) applied the study to the paper's data in silence.
    with pytest.raises(swimbot.SwimbotError, match="ds"):
        s.apply_to(None)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["paper.csv", "s.toml"]
    # A path object and numpy's booleans still work.
    s.add("buoyancy", force=np.bool_(True), diagnose=False)
    assert len(swimbot.Study.open(Path("s.toml")).steps()["step"]) == 1


def test_from_pandas_refuses_what_is_no_frame_setup_or_name_by_name():
    import pandas as pd

    df = pd.read_csv(PAPER_CSV, comment="#")
    for bad in (None, [1, 2], {"id": ["a"]}, np.ones((6, 9)), "paper.csv"):
        with pytest.raises(swimbot.SwimbotError, match="DataFrame"):
            swimbot.Dataset.from_pandas(bad)
    with pytest.raises(swimbot.SwimbotError, match="setup"):
        swimbot.Dataset.from_pandas(df, setup=[("viscosity_pa_s", 3.5)])
    with pytest.raises(swimbot.SwimbotError, match="name"):
        swimbot.Dataset.from_pandas(df, name=None)
    # A setup value TOML cannot hold is refused naming its key (the
    # message named only a line).
    with pytest.raises(swimbot.SwimbotError, match="viscosity_pa_s"):
        swimbot.Dataset.from_pandas(df, setup={"viscosity_pa_s": 10**400})


def test_percentages_are_named_and_the_study_opens_with_the_terminals_numbers(tmp_path):
    cmp = swimbot.compare()
    assert cmp.mare_percent == pytest.approx(100.0 * cmp.mare)
    assert "294.60 %" in cmp._repr_html_()
    data = tmp_path / "paper.csv"
    data.write_text(PAPER_CSV.read_text())
    path = tmp_path / "swimbot-study.toml"
    s = swimbot.Study.init(path, data, diagnose=False)
    s.add("body-correction", diagnose=False)
    rows = s.summary()
    assert rows[0]["what"] == "start (base)" and f"{rows[0]['mare_percent']:.2f}" == "294.60"
    assert rows[1]["what"] == "step 1 body-correction"
    assert rows[1]["mare_before_percent"] == pytest.approx(rows[0]["mare_percent"])
    # The terminal's `steps` prints the same after-value.
    out = subprocess.run(
        [cli_binary(), "--study", str(path), "steps"], capture_output=True, text=True, check=True
    ).stdout
    assert f"{rows[1]['mare_percent']:.2f} %" in out
    assert f"{rows[1]['mare_percent']:.2f} %" in s._repr_html_()


def test_sweep_of_a_study_is_its_calibrated_model_with_the_located_law(tmp_path):
    data = tmp_path / "paper.csv"
    data.write_text(PAPER_CSV.read_text())
    path = tmp_path / "swimbot-study.toml"
    s = swimbot.Study.init(path, data, diagnose=False)
    # As a user runs it: diagnose inside the study writes the law it located.
    subprocess.run([cli_binary(), "--study", str(path), "diagnose", "--write-effect", "found.toml"],
                   cwd=tmp_path, capture_output=True, check=True)
    s.add(tmp_path / "found.toml", diagnose=False)
    law = s.steps()["step"][0]["effect"]["name"]
    assert law.startswith("located-")
    cmp = cli_json("--study", str(path), "compare")["cases"]
    rows = {l.split(",")[0]: l.split(",") for l in PAPER_CSV.read_text().splitlines() if l.startswith("tail-")}
    lam, amp, length, f = (np.array([float(rows[c["id"]][i]) for c in cmp]) for i in (1, 2, 3, 4))
    for c in cmp:
        u, omega = s.sweep(case=c["id"])
        assert (float(u), float(omega)) == (c["u_pred_mm_s"], c["omega_pred_hz"])
    # Every case's geometry at once, on the setup they share.
    u, omega = swimbot.sweep(lam, amp, length, f, study=s)
    assert u.tolist() == [c["u_pred_mm_s"] for c in cmp]
    assert omega.tolist() == [c["omega_pred_hz"] for c in cmp]
    # The study's law is no catalogue effect: named alone it is refused, and
    # with the study it is a contradiction, both said by name.
    with pytest.raises(swimbot.SwimbotError, match=f"unknown effect `{law}`"):
        swimbot.sweep(effects=[law])
    with pytest.raises(swimbot.SwimbotError, match="study and preset/effects"):
        swimbot.sweep(study=s, effects=["body-correction"])
    with pytest.raises(swimbot.SwimbotError, match="swimbot.Study"):
        swimbot.sweep(study=str(path))


def paper_frame():
    """The paper's CSV as a DataFrame and its ``# key = value`` lines as a
    setup mapping."""
    import pandas as pd
    import tomllib

    text = PAPER_CSV.read_text()
    setup = tomllib.loads("\n".join(l[2:] for l in text.splitlines() if re.match(r"# [a-z0-9_.]+ = ", l)))
    return pd.read_csv(PAPER_CSV, comment="#"), setup


def frame_error(df, setup) -> str:
    with pytest.raises(swimbot.SwimbotError) as e:
        swimbot.Dataset.from_pandas(df, setup=setup)
    message = str(e.value)
    # Said of the DataFrame, never of the CSV text it was written as.
    assert "row " not in message and "line " not in message and "# " not in message, message
    return message


def test_from_pandas_errors_name_the_frames_column_and_index():
    import pandas as pd

    df, setup = paper_frame()
    assert len(swimbot.Dataset.from_pandas(df, setup=setup)) == 6  # the setup's `name` included
    bad = df.astype({"wavelength_mm": object})
    bad.loc[2, "wavelength_mm"] = "abc"
    assert frame_error(bad, setup) == (
        "tabak-yesilyurt-vertical: column 'wavelength_mm', index 2 (case 'tail-3'): `abc` is not a number"
    )
    nan = df.copy()
    nan.loc[4, "wavelength_mm"] = float("nan")
    assert "column 'wavelength_mm', index 4 (case 'tail-5'): NaN, read as missing" in frame_error(nan, setup)
    missing = frame_error(df.drop(columns=["wavelength_mm"]), setup)
    assert "no column 'wavelength_mm'" in missing and "index 0 (case 'tail-1')" in missing, missing
    # An index of texts and one of numbers: each named by its label.
    text = df.set_axis(["a", "b", "c", "d", "e", "f"])
    text.loc["d", "amplitude_mm"] = -1.0
    assert "column 'amplitude_mm', index 'd' (case 'tail-4'): must be positive" in frame_error(text, setup)
    ints = df.set_axis([10, 20, 30, 40, 50, 60])
    ints.loc[50, "u_mm_s"] = float("inf")
    assert "column 'u_mm_s', index 50 (case 'tail-5'): must be finite" in frame_error(ints, setup)
    # A setup value is named as the setup key it is.
    assert "setup key 'viscosity_pa_s', for index 0 (case 'tail-1'): must be positive" in frame_error(
        df, dict(setup, viscosity_pa_s=-3.5)
    )
    # A multi-line text cell does not shift the rows the labels are read from.
    note = df.assign(note=["one\ntwo", "", "", "", "", ""])
    note.loc[5, "amplitude_mm"] = -1.0
    assert "index 5 (case 'tail-6')" in frame_error(note, setup)


def test_from_pandas_takes_the_ids_from_an_index_named_id():
    df, setup = paper_frame()
    ds = swimbot.Dataset.from_pandas(df.set_index("id"), setup=setup)
    assert ds.ids == df["id"].tolist()


def test_diagnose_parameters_are_the_terminals_and_say_how_their_interval_was_made():
    d = swimbot.diagnose()
    assert d.headline == cli_json("diagnose")["headline"]
    params = d.parameters
    assert params, d.headline
    for p in params:
        assert p["interval"] in ("covariance", "profile") and isinstance(p["value"], float), p
        if p["interval"] == "covariance" and p["ci95_low"] is not None:
            assert p["ci95_high"] - p["value"] == pytest.approx(1.96 * p["standard_uncertainty"])
            assert p["value"] - p["ci95_low"] == pytest.approx(1.96 * p["standard_uncertainty"])
    for c in d.correlations:
        assert isinstance(c["r"], float) and abs(c["r"]) > 0.8, c
