"""A notebook session as a script: the paper's CSV and a European export of
it, compared, diagnosed, 10^5 geometries swept, a result rendered as HTML;
every number asserted equal to the CLI's (``$SWIMBOT_BIN`` or
``target/debug/swimbot``).

    python python/examples/notebook.py
"""

import json
import os
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

import swimbot

ROOT = Path(__file__).resolve().parents[2]
PAPER_CSV = ROOT / "host" / "data" / "paper.csv"
CLI = os.environ.get("SWIMBOT_BIN") or str(ROOT / "target" / "debug" / "swimbot")


def cli_json(*args):
    out = subprocess.run([CLI, *args, "--format", "json"], capture_output=True, text=True, check=True)
    doc = json.loads(out.stdout)
    doc.pop("swimbot")
    return doc


def european(text):
    rows = []
    for line in text.splitlines():
        if line.startswith("#"):
            rows.append(line)
            continue
        cells = []
        for c in line.split(","):
            try:
                float(c)
                cells.append(c.replace(".", ","))
            except ValueError:
                cells.append(c)
        rows.append(";".join(cells))
    return "\ufeff" + "\r\n".join(rows) + "\r\n"


# In [1]: the paper's CSV, and the same sheet saved by a European spreadsheet.
ds = swimbot.load(PAPER_CSV)
with tempfile.TemporaryDirectory() as tmp:
    eu_path = Path(tmp) / "paper-eu.csv"
    eu_path.write_text(european(PAPER_CSV.read_text()), encoding="utf-8", newline="")
    eu = swimbot.load(eu_path)
print(ds, "|", eu.note)

# In [2]: compare, as `swimbot compare --format json`.
cmp = swimbot.compare(ds)
assert cmp.to_dict() == cli_json("compare", "--no-report", "--data", str(PAPER_CSV))
assert swimbot.compare(eu).to_dict() == cmp.to_dict()
print(f"MARE {cmp.mare:.3f}, reduced chi-square {cmp.chi2_reduced:.1f}")

# In [3]: where the model fails, and what is missing.
d = swimbot.diagnose(ds)
assert d.to_dict() == cli_json("diagnose", "--data", str(PAPER_CSV))
print("strongest trend:", d.trends[0]["quantity"], d.trends[0]["feature"], round(d.trends[0]["r"], 3))

# In [4]: 10^5 geometries, broadcast: 100 wavelengths x 1000 amplitudes.
lam = np.linspace(8.0, 16.0, 100)[:, None]
amp = np.linspace(1.5, 7.5, 1000)[None, :]
t0 = time.perf_counter()
u, omega = swimbot.sweep(wavelength_mm=lam, amplitude_mm=amp, tail_length_mm=88.0, frequency_hz=1.5)
took = time.perf_counter() - t0
assert u.shape == omega.shape == (100, 1000) and np.isfinite(u).all()
print(f"sweep: {u.size} geometries in {took:.2f} s ({1e6 * took / u.size:.2f} us each)")
# The sweep's numbers are the model's: the paper's tails give compare's predictions.
cases = [l.split(",") for l in PAPER_CSV.read_text().splitlines() if l.startswith("tail-")]
cols = [np.array([float(r[i]) for r in cases]) for i in (1, 2, 3, 4)]
u6, _ = swimbot.sweep(*cols)
assert u6.tolist() == [c["u_pred_mm_s"] for c in cmp.to_dict()["cases"]]

# In [5]: what a notebook cell shows.
page = cmp._repr_html_()
assert "<table>" in page and "<svg" in page
print(f"HTML: {len(page)} characters, {page.count('<svg')} figures")
