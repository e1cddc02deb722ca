"""The attack on the Python package's `Study` API and `Dataset.from_pandas`:
calls with wrong types, NaN, None, huge frames, and a study changed on
disk between two calls. A call must return finite numbers, or raise
`swimbot.SwimbotError` naming the argument or file; never another
exception, a crash, a silent wrong result, or a file written where it was
not asked for.
"""

import json
import math
import os
import shutil
from pathlib import Path

from attack_common import PAPER_CSV, record


def finite(x):
    """Every number in a JSON-like value is finite."""
    if isinstance(x, float):
        return math.isfinite(x)
    if isinstance(x, dict):
        return all(finite(v) for v in x.values())
    if isinstance(x, (list, tuple)):
        return all(finite(v) for v in x)
    return True


def attempt(cat, name, f, must=(), accept=False, check=None):
    """`f()` must raise SwimbotError naming `must`, or (with `accept`)
    return a value `check` finds nothing wrong with."""
    import swimbot

    try:
        r = f()
    except swimbot.SwimbotError as e:
        miss = [m for m in must if m not in str(e)]
        return record(cat, name, f"message does not name {miss}" if miss else None, "", str(e))
    except MemoryError:
        return record(cat, name, "MemoryError (allocated before refusing)")
    except Exception as e:  # noqa: BLE001
        return record(cat, name, f"{type(e).__name__} instead of SwimbotError", "", str(e)[:300])
    if not accept:
        return record(cat, name, "accepted")
    why = None
    if isinstance(r, dict) and not finite(r):
        why = "non-finite numbers returned"
    elif check is not None:
        why = check(r)
    return record(cat, name, why)


def attack_study_api(tmp):
    import numpy as np

    import swimbot

    tmp = Path(tmp)
    cat = "Python Study: wrong types, NaN, None"
    d = tmp / "py"
    d.mkdir()
    shutil.copy(PAPER_CSV, d / "paper.csv")
    os.chdir(d)
    good = swimbot.Study.init(d / "s.toml", d / "paper.csv", diagnose=False)
    bads = [None, 42, 3.5, float("nan"), b"s.toml", ["s.toml"], {"a": 1}, object(), np.float64("nan"), True, ""]
    for b in bads:
        label = repr(b)[:30]
        attempt(cat, f"Study.init(path={label})", lambda: swimbot.Study.init(b, d / "paper.csv", diagnose=False))
        attempt(cat, f"Study.init(data={label})", lambda: swimbot.Study.init(d / "x.toml", b, diagnose=False))
        # A bytes path is a path (os.fsdecode): it opens the study there.
        attempt(cat, f"Study.open({label})", lambda: swimbot.Study.open(b), accept=isinstance(b, bytes))
        attempt(cat, f"Study.add({label})", lambda: good.add(b))
        attempt(cat, f"Study.apply_to({label})", lambda: good.apply_to(b))
        attempt(cat, f"Study.report({label})", lambda: good.report(b))
        attempt(cat, f"Study.init(preset={label})",
                lambda: swimbot.Study.init(d / "y.toml", d / "paper.csv", preset=b, diagnose=False))
        attempt(cat, f"Study.init(likelihood={label})",
                lambda: swimbot.Study.init(d / "z.toml", d / "paper.csv", likelihood=b, diagnose=False))
        attempt(cat, f"Study.add(refit_all={label})", lambda: good.add("buoyancy", refit_all=b, diagnose=False),
                accept=isinstance(b, bool))
        if isinstance(b, bool) and good.steps().get("step"):
            good.undo()
    strays = sorted(p.name for p in d.iterdir() if p.name not in {"paper.csv", "s.toml"})
    record(cat, "no file written by a refused call", f"left {strays[:6]}" if strays else None)
    for p in d.iterdir():
        if p.name not in {"paper.csv", "s.toml"}:
            shutil.rmtree(p) if p.is_dir() else p.unlink()
    attempt(cat, "Study.add('') ", lambda: good.add(""))
    attempt(cat, "Study.add('#')", lambda: good.add("#"))
    attempt(cat, "Study.add(a 10^5-character name)", lambda: good.add("x" * 100_000))
    attempt(cat, "Study.undo() with no step", lambda: good.undo(), must=("s.toml",))
    attempt(cat, "Study.report onto the dataset", lambda: good.report(d / "paper.csv"), must=("paper.csv",))
    attempt(cat, "Study.report onto the study", lambda: good.report(d / "s.toml"), must=("s.toml",))
    attempt(cat, "Study.report onto /dev/full", lambda: good.report("/dev/full"), must=("/dev/full",))
    attempt(cat, "Study.report into its own folder", lambda: good.report(d), must=(str(d),))
    attempt(cat, "Study.init over the dataset", lambda: swimbot.Study.init(d / "paper.csv", d / "paper.csv",
                                                                           force=True, diagnose=False),
            must=("paper.csv",))
    attempt(cat, "Study.init(data=the study)", lambda: swimbot.Study.init(d / "w.toml", d / "s.toml",
                                                                          diagnose=False), must=("s.toml",))
    df = __import__("pandas").read_csv(PAPER_CSV, comment="#")
    setup = {"wire_diameter_mm": 1.0, "channel_diameter_mm": 35.0, "channel_length_mm": 350.0,
             "viscosity_pa_s": 3.5, "density_kg_m3": 985.0, "body_diameter_mm": 20.0, "body_length_mm": 50.0,
             "coupler_diameter_mm": 6.0, "coupler_length_mm": 10.0, "trials": 5}
    nan_frame = df.assign(u_mm_s=[np.nan] * 6)
    attempt(cat, "Study.apply_to(from_pandas, every speed NaN)",
            lambda: good.apply_to(swimbot.Dataset.from_pandas(nan_frame, setup=setup)), must=("u_mm_s",),
            accept=True)
    ok = swimbot.Dataset.from_pandas(df, setup=setup)
    attempt(cat, "Study.apply_to(from_pandas of the paper)", lambda: good.apply_to(ok), accept=True)

    cat = "Python Dataset.from_pandas: hostile frames and setups"
    F = swimbot.Dataset.from_pandas
    pd = __import__("pandas")
    frames = {
        "None": None, "a list": [1, 2], "a dict": {"id": ["a"]}, "a numpy array": np.ones((6, 9)),
        "a Series": df["u_mm_s"], "a string": "paper.csv",
        "None in wavelength_mm": df.assign(wavelength_mm=[None] + list(df.wavelength_mm[1:])),
        "pd.NA in u_mm_s": df.astype({"u_mm_s": "Float64"}).assign(u_mm_s=pd.array([pd.NA] + list(df.u_mm_s[1:]), dtype="Float64")),
        "object column of floats and text": df.assign(amplitude_mm=[2.5, "2.5 mm", 4.5, 4.5, 7.5, 7.5]),
        "numbers as text in an object column": df.assign(amplitude_mm=[str(v) for v in df.amplitude_mm]),
        "bool column as a quantity": df.assign(frequency_hz=True),
        "datetime column": df.assign(when=pd.Timestamp("2024-01-01")),
        "categorical ids": df.assign(id=df.id.astype("category")),
        "integer ids": df.assign(id=range(6)),
        "MultiIndex columns": pd.DataFrame(df.values, columns=pd.MultiIndex.from_tuples([(c, "x") for c in df.columns])),
        "duplicate columns": pd.concat([df, df[["u_mm_s"]]], axis=1),
        "a column named with a newline": df.rename(columns={"u_ci_mm_s": "u_ci\nmm_s"}),
        "a column named # name = x": df.assign(**{"# name = x": 1.0}),
        "the first column named # viscosity_pa_s = 9": pd.concat([pd.DataFrame({"# viscosity_pa_s = 9": [1.0] * 6}), df],
                                                                axis=1),
        "unicode column names": df.assign(**{"\u00b5\U0001F41F": 1.0}),
        "a 10^5-character label": df.assign(operator="o" * 100_000),
        "1e308 speeds": df.assign(u_mm_s=1e308),
        "negative frequencies": df.assign(frequency_hz=-df.frequency_hz),
        "10^6 rows": pd.concat([df] * 166_667, ignore_index=True),
        "10^4 columns": pd.concat([df, pd.DataFrame(np.ones((6, 10_000)), columns=[f"c{i}" for i in range(10_000)])],
                                  axis=1),
        "index not 0..n": df.set_index(pd.Index([10, 3, 7, 1, 2, 99])),
        "ids with commas and quotes": df.assign(id=[f'a,"{i}"' for i in range(6)]),
    }
    must = {"None in wavelength_mm": ("wavelength_mm",), "pd.NA in u_mm_s": ("u_mm_s",),
            "object column of floats and text": ("amplitude_mm",), "10^6 rows": ("10000",)}
    accept = {"numbers as text in an object column", "a column named # name = x", "categorical ids", "integer ids", "unicode column names", "index not 0..n", "datetime column",
              "ids with commas and quotes", "a 10^5-character label", "10^4 columns"}
    ref = swimbot.compare(ok).mare
    for name, frame in frames.items():
        def same(ds):
            m = swimbot.compare(ds).mare
            return None if m == ref else f"MARE {m} != {ref}"
        attempt(cat, f"from_pandas({name})", lambda: F(frame, setup=setup), must=must.get(name, ()),
                accept=name in accept, check=same if name in accept and name != "datetime column" else None)
    setups = {"None value": None, "nested dict": {"a": 1}, "10**400": 10**400, "-1e308": -1e308, "a list of NaN": [math.nan],
              "a set": {1.0}, "bytes": b"3.5", "empty string": "", "numpy NaN": np.float64("nan"),
              "numpy int": np.int64(3), "string with a newline": "3.5\n# trials = 1"}
    for name, v in setups.items():
        accept_it = name in {"numpy int"}
        attempt(cat, f"from_pandas(setup viscosity_pa_s = {name})",
                lambda: F(df, setup={**setup, "viscosity_pa_s": v}), must=("viscosity_pa_s",), accept=accept_it)
    attempt(cat, "from_pandas(setup=a list)", lambda: F(df, setup=[("viscosity_pa_s", 3.5)]), must=("setup",))
    attempt(cat, "from_pandas(name=None)", lambda: F(df, setup=setup, name=None), must=("name",))
    attempt(cat, "from_pandas(name=10^5 characters)", lambda: F(df, setup=setup, name="n" * 100_000), accept=True)

    cat = "Python Study: changed on disk between calls"
    changes = {
        "study deleted": lambda d: (d / "s.toml").unlink(),
        "study truncated": lambda d: (d / "s.toml").write_text((d / "s.toml").read_text()[:200]),
        "study replaced by another study": lambda d: shutil.copy(d / "other.toml", d / "s.toml"),
        "a step added by another writer": lambda d: swimbot.Study.open(d / "s.toml").add("tail-confinement", force=True,
                                                                                         diagnose=False),
        "undone by another writer": lambda d: swimbot.Study.open(d / "s.toml").undo(),
        "dataset edited": lambda d: (d / "paper.csv").write_text((d / "paper.csv").read_text().replace("0.586", "0.587")),
        "dataset deleted": lambda d: (d / "paper.csv").unlink(),
        "dataset replaced by /dev/zero": lambda d: ((d / "paper.csv").unlink(), (d / "paper.csv").symlink_to("/dev/zero")),
        "study made a folder": lambda d: ((d / "s.toml").unlink(), (d / "s.toml").mkdir()),
        "study 1 byte appended": lambda d: (d / "s.toml").write_text((d / "s.toml").read_text() + "#"),
    }
    calls = {
        "add": lambda s: s.add("buoyancy", force=True, diagnose=False),
        "undo": lambda s: s.undo(),
        "report": lambda s: s.report("rep"),
        "steps": lambda s: s.steps(),
        "apply_to": lambda s: s.apply_to(swimbot.paper()),
    }
    base = tmp / "pybase"
    base.mkdir()
    shutil.copy(PAPER_CSV, base / "paper.csv")
    s0 = swimbot.Study.init(base / "s.toml", base / "paper.csv", diagnose=False)
    s0.add("body-correction", force=True, diagnose=False)
    swimbot.Study.init(base / "other.toml", base / "paper.csv", diagnose=False)
    k = 0
    for cname, change in changes.items():
        for call, f in calls.items():
            d = tmp / f"pc{k}"
            k += 1
            shutil.copytree(base, d)
            s = swimbot.Study.open(d / "s.toml")
            change(d)
            before = snapshot_text(d)
            # Writing calls must be refused or act on what the file now
            # is; reads (steps, apply_to) may answer from what was opened.
            writes = call in ("add", "undo")
            try:
                r = f(s)
            except swimbot.SwimbotError as e:
                why = None if any(n in str(e) for n in ("s.toml", "paper.csv", "changed")) else "message names no file"
                if not why and snapshot_text(d) != before:
                    why = "refused, and the files changed"
                record(cat, f"{cname}: {call}", why, "", str(e))
                continue
            except Exception as e:  # noqa: BLE001
                record(cat, f"{cname}: {call}", f"{type(e).__name__} instead of SwimbotError", "", str(e)[:300])
                continue
            why = None
            if isinstance(r, dict) and not finite(r):
                why = "non-finite numbers returned"
            elif writes and cname not in ("dataset deleted",):
                # What the file holds now must be what the call said.
                try:
                    now = json.loads(json.dumps(swimbot.Study.open(d / "s.toml").steps()))
                    mine = s.steps()
                    if now != mine:
                        why = "the object and the file disagree after the call"
                except swimbot.SwimbotError as e:
                    why = f"accepted, and the file no longer opens: {str(e)[:120]}"
            record(cat, f"{cname}: {call}", why)
            shutil.rmtree(d, ignore_errors=True)
    os.chdir(tmp)


def snapshot_text(d):
    out = {}
    for p in sorted(Path(d).rglob("*")):
        if p.is_file() and not p.is_symlink():
            out[str(p)] = p.read_bytes()
    return out
