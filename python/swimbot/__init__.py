"""swimbot from Python: the resistive-force-theory model of a helical-tail
swimming robot, compared with a lab's measurements.

Every number comes from the Rust library through the CLI's own code
(``swimbot._swimbot``), so ``result.to_dict()`` equals the command's
``--format json`` output (its provenance block left out)::

    import swimbot
    ds = swimbot.load("host/data/paper.csv")        # CSV or TOML
    cmp = swimbot.compare(ds, effects=["tail-confinement"])
    cmp.mare, cmp.chi2_reduced
    cmp.to_pandas()                                  # one row per case
    u, omega = swimbot.sweep(wavelength_mm=np.linspace(8, 16, 100),
                             amplitude_mm=2.5, tail_length_mm=88)

pandas is optional: only ``to_pandas`` and ``Dataset.from_pandas`` need it.
Bad input raises :class:`SwimbotError` with the CLI's message (file, case,
field).
"""

from __future__ import annotations

import html
import json
import math
import re
import os
import warnings
from os import PathLike
from typing import Any, Iterable, Mapping, Optional, Sequence

from . import _swimbot
from ._swimbot import SwimbotError

__all__ = [
    "SwimbotError",
    "Dataset",
    "load",
    "paper",
    "compare",
    "diagnose",
    "fit",
    "audit",
    "sweep",
    "Comparison",
    "Diagnosis",
    "Fit",
    "Audit",
    "Study",
    "MAX_SWEEP_GEOMETRIES",
]


class Dataset:
    """A validated dataset: a setup and, per case, a tail geometry, its
    tail rate and (optionally) the measured speed and body rotation."""

    def __init__(self, inner: "_swimbot.Dataset"):
        self._inner = inner

    @property
    def name(self) -> str:
        return self._inner.name

    @property
    def source(self) -> str:
        return self._inner.source

    @property
    def ids(self) -> list:
        """The case ids, in the file's order."""
        return list(self._inner.ids)

    @property
    def note(self) -> Optional[str]:
        """What the reader took as what (a spreadsheet's dialect, recorded
        columns), when it was not the format's own."""
        return self._inner.note

    def __len__(self) -> int:
        return len(self._inner)

    def __repr__(self) -> str:
        return repr(self._inner)

    @classmethod
    def from_pandas(
        cls,
        df: Any,
        setup: Optional[Mapping[str, Any]] = None,
        name: str = "<pandas>",
    ) -> "Dataset":
        """A dataset from a DataFrame with the CSV format's columns (one row
        per case, or per trial with a shared ``id``; docs/data-format.md)
        and ``setup`` as the ``[setup]`` defaults. Columns that are no
        dataset field are kept as recorded variables (numbers) or labels."""
        if not (hasattr(df, "to_csv") and hasattr(df, "columns")):
            raise SwimbotError(f"df: {type(df).__name__} is not a pandas DataFrame")
        if setup is not None and not isinstance(setup, Mapping):
            raise SwimbotError(f"setup: {type(setup).__name__} is not a mapping of setup keys to values")
        setup = dict(setup or {})
        if "name" in setup:
            # The dataset's name is one line; two would be a duplicate key.
            given = setup.pop("name")
            if name != "<pandas>" and given != name:
                raise SwimbotError(f"setup: name = {given!r} and name = {name!r}: give the dataset's name once")
            name = given
        if "id" not in df.columns and getattr(df.index, "name", None) == "id":
            # `df.set_index("id")`: the ids are the index, and `to_csv`
            # below leaves the index out.
            df = df.reset_index()
        lines = [f"# name = {_toml(_text('name', name))}"]
        for key, value in setup.items():
            # A key is one `# key = value` line: a newline in it would
            # start a line of its own (a forged setup line or header).
            if not isinstance(key, str) or not re.fullmatch(r"[A-Za-z0-9_.]+", key):
                raise SwimbotError(f"setup: {key!r} is not a setup key (letters, digits, `_` and `.`)")
            if isinstance(value, float) and not math.isfinite(value):
                raise SwimbotError(f"setup: {key} = {value}: not a finite number")
            try:
                lines.append(f"# {key} = {_toml(value)}")
            except SwimbotError as e:
                raise SwimbotError(f"setup: {key}: {e}") from None
        body = df.to_csv(index=False, float_format="%.17g")
        text = "\n".join(lines) + "\n" + body
        try:
            return cls(_noted(_swimbot.from_csv(text, name)))
        except SwimbotError as e:
            raise SwimbotError(_frame_message(str(e), name, df, lines, body)) from None


#: The CSV reader's place in a message: `NAME: row N` or `NAME: line N`,
#: then a column, a case and a field, each optional, then what is wrong.
_AT = r": (?P<kind>row|line) (?P<n>\d+)(?:: column `(?P<column>[^`]*)`)?(?:: case `(?P<case>[^`]*)`)?" \
      r"(?:: field `(?P<field>[^`]*)`)?: (?P<what>.*)"


def _frame_message(message: str, name: str, df: Any, lines: list, body: str) -> str:
    """The CSV reader's message about the text ``from_pandas`` wrote, said
    of the DataFrame: its column and index label instead of a CSV row, the
    setup key instead of a ``# key = value`` line. A message of another
    shape is returned as it is."""
    import csv
    import io

    m = re.fullmatch(re.escape(name) + _AT, message, flags=re.S)
    if not m:
        return message
    what = m["what"].replace("a `# key = value` line above the column names", "a setup key")
    n = int(m["n"])
    if n <= len(lines):
        key = lines[n - 1][2:].split(" = ")[0]
        what = re.sub(r"^`# [^`]*`: ", "", what)
        return f"{name}: setup key {key!r}: {what}"
    # Each record's first line in `body` (a text cell may hold a newline).
    reader = csv.reader(io.StringIO(body))
    starts, seen = [], 0
    for _ in reader:
        starts.append(seen + 1)
        seen = reader.line_num
    line = n - len(lines)
    position = max((k for k, s in enumerate(starts) if s <= line), default=0) - 1
    if position < 0:
        return f"{name}: the DataFrame's columns: {what}"
    label = df.index[position]
    label = label.item() if hasattr(label, "item") else label
    column = m["column"] or m["field"]
    case = f" (case {m['case']!r})" if m["case"] and m["case"] != str(label) else ""
    where = f"index {label!r}{case}"
    if column is None:
        return f"{name}: {where}: {what}"
    keys = {l[2:].split(" = ")[0] for l in lines}
    if column in keys and column not in df.columns:
        # Not a column: the value came from the setup.
        return f"{name}: setup key {column!r}, for {where}: {what}"
    if column not in df.columns:
        have = ", ".join(map(str, df.columns))
        return f"{name}: no column {column!r} (the DataFrame has {have}) and no setup key of it, needed at {where}: {what}"
    if _missing(df[column].iloc[position]):
        what = re.sub(r"^missing( \(give it a column, or a setup key\))?", "NaN, read as missing", what)
    return f"{name}: column {column!r}, {where}: {what}"


def _missing(value: Any) -> bool:
    return isinstance(value, float) and math.isnan(value) or value is None


def _toml(value: Any) -> str:
    """A Python value as a TOML value (numbers, text, booleans, lists)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return repr(float(value)) if isinstance(value, float) else str(value)
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, Mapping):
        return "{ " + ", ".join(f"{k} = {_toml(v)}" for k, v in value.items()) + " }"
    if isinstance(value, Iterable):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    raise SwimbotError(f"{value!r} is not a number, text, boolean or list")


def _noted(inner: "_swimbot.Dataset") -> "_swimbot.Dataset":
    if inner.note:
        warnings.warn(inner.note, stacklevel=3)
    return inner


def load(path: Any, decimal_comma: bool = False) -> Dataset:
    """Read a dataset file: CSV (``.csv``; ``,`` ``;`` or tab between cells,
    decimal commas detected or forced with ``decimal_comma``) or TOML."""
    return Dataset(_noted(_swimbot.load(_path("path", path), _bool("decimal_comma", decimal_comma))))


def paper() -> Dataset:
    """The paper's six tails (built in)."""
    return Dataset(_swimbot.paper())


def _data(ds: Optional[Dataset]) -> "_swimbot.Dataset":
    if ds is None:
        return _swimbot.paper()
    if isinstance(ds, Dataset):
        return ds._inner
    return load(ds)._inner


def _texts(name: str, values: Any) -> list:
    """A list of texts (one text is a list of one); anything else is
    refused naming the argument."""
    if isinstance(values, (str, PathLike)):
        values = [values]
    if not isinstance(values, Iterable) or isinstance(values, (bytes, Mapping)):
        raise SwimbotError(f"{name}: {values!r} is not a list of names")
    out = []
    for v in values:
        if not isinstance(v, (str, PathLike)):
            raise SwimbotError(f"{name}: {v!r} is not a name ({type(v).__name__})")
        out.append(str(v))
    return out


def _flag(name: str, value: Any) -> str:
    """``--name=value``: one argument, so that a value starting with `-`
    (``mc_draws=-1``) reaches the flag's own check instead of reading as
    another flag."""
    return f"--{name}={value}"


def _path(name: str, value: Any) -> str:
    """A path argument: text or an ``os.PathLike`` (bytes decoded as the
    file system does). Anything else is refused naming the argument:
    ``str(None)`` made a file called ``None``."""
    if isinstance(value, (str, bytes, PathLike)):
        path = os.fsdecode(os.fspath(value))
        if path:
            return path
        raise SwimbotError(f"{name}: an empty path")
    raise SwimbotError(f"{name}: {value!r} is not a path ({type(value).__name__})")


def _text(name: str, value: Any) -> str:
    if isinstance(value, str):
        return value
    raise SwimbotError(f"{name}: {value!r} is not a text ({type(value).__name__})")


def _bool(name: str, value: Any) -> bool:
    """True or False (numpy's too); 0, 1, None or a text are refused: a
    flag given a count or a word is a mistake to say, not to guess."""
    numpy_bool = getattr(getattr(value, "dtype", None), "kind", None) == "b" and getattr(value, "ndim", 1) == 0
    if isinstance(value, bool) or numpy_bool:
        return bool(value)
    raise SwimbotError(f"{name}: {value!r} is not True or False")


def _model_args(preset: Optional[str], effects: Sequence[str], effect_files: Sequence[Any]) -> list:
    args = []
    if preset is not None:
        args.append(_flag("preset", _texts("preset", preset)[0]))
    args += [_flag("effect", e) for e in _texts("effects", effects)]
    args += [_flag("effect-file", f) for f in _texts("effect_files", effect_files)]
    return args


class _Result:
    """A command's result: its JSON document as a dict, plus views."""

    _title = "swimbot"

    def __init__(self, document: str, figures: Sequence[str] = ()):
        self._dict = json.loads(document)
        self._figures = list(figures)

    def to_dict(self) -> dict:
        """The command's ``--format json`` document (without the provenance block)."""
        return json.loads(json.dumps(self._dict))

    @property
    def figures(self) -> list:
        """The report's figures (SVG text)."""
        return list(self._figures)

    def _rows(self) -> list:
        return []

    def to_pandas(self):
        """One row per case (pandas needed)."""
        import pandas as pd

        return pd.DataFrame(self._rows())

    def _repr_html_(self) -> str:
        rows = self._rows()
        parts = [f"<h4>{html.escape(self._title)}</h4>", self._summary_html()]
        if rows:
            cols = list(rows[0].keys())
            head = "".join(f"<th>{html.escape(c)}</th>" for c in cols)
            body = "".join(
                "<tr>" + "".join(f"<td>{_cell(r.get(c))}</td>" for c in cols) + "</tr>"
                for r in rows
            )
            parts.append(f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>")
        parts += [f"<div>{svg}</div>" for svg in self._figures]
        return "\n".join(parts)

    def _summary_html(self) -> str:
        return ""


def _cell(v: Any) -> str:
    if isinstance(v, float):
        return f"{v:.4g}"
    if v is None:
        return ""
    return html.escape(str(v))


class Comparison(_Result):
    """``swimbot compare``: model against measurement, per case and in summary."""

    _title = "swimbot compare"

    @property
    def mare(self) -> float:
        """Mean absolute relative error over the measured quantities, as a
        fraction (2.946 is the terminal's 294.6 %); see ``mare_percent``."""
        return self._dict["summary"]["mare"]

    @property
    def mare_percent(self) -> float:
        """``mare`` in percent, as the terminal and the page print it."""
        return 100.0 * self.mare

    @property
    def chi2_reduced(self) -> float:
        """Reduced chi-square against the measurement's standard errors."""
        return self._dict["summary"]["chi2_reduced"]

    @property
    def model(self) -> str:
        return self._dict["model"]

    def _rows(self) -> list:
        rows = []
        for c in self._dict["cases"]:
            row = {k: v for k, v in c.items() if k != "recorded"}
            row.update(c.get("recorded", {}))
            rows.append(row)
        return rows

    def _summary_html(self) -> str:
        return (
            f"<p>model: {html.escape(self.model)}; MARE {self.mare_percent:.2f} %; "
            f"reduced chi-square {self.chi2_reduced:.4g}</p>"
        )


class Diagnosis(_Result):
    """``swimbot diagnose``: where the model fails and which effect closes the gap."""

    _title = "swimbot diagnose"

    @property
    def trends(self) -> list:
        """Residual trends against the features, strongest first."""
        return self._dict.get("trends", [])

    @property
    def verdict(self) -> Any:
        return self._dict.get("verdict")

    @property
    def headline(self) -> dict:
        """The answer as the terminal's screen prints it (the JSON's
        ``headline``): the verdict's kind, each step's law with its
        parameters, MARE (fractions) and reduced chi-square before ->
        after, the rivals and the next command."""
        return self._dict.get("headline", {})

    @property
    def parameters(self) -> list:
        """Every step's parameters as the terminal reports them, one dict
        each with the step's ``law``: ``value``, ``standard_uncertainty``,
        ``relative_uncertainty_percent`` (in percent), the 95 % interval
        ``ci95_low`` .. ``ci95_high`` and ``interval``, which says how it was
        made: ``"covariance"`` (value ± 1.96 u) or ``"profile"`` (the
        profile likelihood's, where it is asymmetric)."""
        return [dict(p, law=s["law"]) for s in self.headline.get("steps", []) for p in s["params"]]

    @property
    def correlations(self) -> list:
        """Pairs of one step's parameters correlated beyond 0.8: ``a``,
        ``b``, the correlation ``r`` and the step's ``law``."""
        return [dict(c, law=s["law"]) for s in self.headline.get("steps", []) for c in s.get("correlations", [])]

    def _rows(self) -> list:
        return [
            {k: t.get(k) for k in ("quantity", "feature", "feature_id", "r", "slope")}
            for t in self.trends
        ]


class Fit(_Result):
    """``swimbot fit``: effect parameters calibrated on the data."""

    _title = "swimbot fit"

    @property
    def estimates(self) -> list:
        return self._dict["fit"]["estimates"]

    @property
    def comparison(self) -> dict:
        return self._dict["comparison"]

    @property
    def mare(self) -> float:
        """MARE after the fit, as a fraction; see ``mare_percent``."""
        return self._dict["comparison"]["summary"]["mare"]

    @property
    def mare_percent(self) -> float:
        """``mare`` in percent, as the terminal prints it."""
        return 100.0 * self.mare

    @property
    def chi2_reduced(self) -> float:
        return self._dict["comparison"]["summary"]["chi2_reduced"]

    def _rows(self) -> list:
        return Comparison(json.dumps(self.comparison))._rows()

    def _summary_html(self) -> str:
        items = "".join(
            f"<li>{html.escape(str(e.get('effect')))}.{html.escape(str(e.get('name')))} = "
            f"{_cell(e.get('value'))} ± {_cell(e.get('ci95'))}</li>"
            for e in self.estimates
        )
        return f"<ul>{items}</ul>"


class Audit(_Result):
    """``swimbot audit``: checks of the data themselves."""

    _title = "swimbot audit"

    @property
    def flags(self) -> list:
        return self._dict.get("flags", [])

    def _rows(self) -> list:
        return [dict(f) for f in self.flags]


def compare(
    ds: Optional[Dataset] = None,
    preset: Optional[str] = None,
    effects: Sequence[str] = (),
    effect_files: Sequence[Any] = (),
    input_uncertainty: bool = False,
    mc_draws: int = 300,
) -> Comparison:
    """``swimbot compare`` on ``ds`` (default: the paper's data)."""
    args = _model_args(preset, effects, effect_files) + [_flag("mc-draws", mc_draws)]
    if input_uncertainty:
        args.append("--input-uncertainty")
    return Comparison(*_swimbot.compare(_data(ds), args))


def diagnose(
    ds: Optional[Dataset] = None,
    preset: Optional[str] = None,
    effects: Sequence[str] = (),
    effect_files: Sequence[Any] = (),
    discovery: bool = True,
    pairs: bool = True,
    input_uncertainty: bool = False,
    extra_args: Sequence[str] = (),
) -> Diagnosis:
    """``swimbot diagnose`` on ``ds``; ``extra_args`` are further CLI flags."""
    args = _model_args(preset, effects, effect_files) + list(extra_args)
    if not discovery:
        args.append("--no-discovery")
    if not pairs:
        args.append("--no-pairs")
    if input_uncertainty:
        args.append("--input-uncertainty")
    return Diagnosis(_swimbot.diagnose(_data(ds), args))


def fit(
    ds: Optional[Dataset] = None,
    effects: Sequence[str] = (),
    preset: Optional[str] = None,
    effect_files: Sequence[Any] = (),
    cases: Sequence[str] = (),
) -> Fit:
    """``swimbot fit``: calibrate ``effects``' free parameters on ``ds``."""
    args = _model_args(preset, effects, effect_files)
    for c in _texts("cases", cases):
        args.append(_flag("cases", c))
    return Fit(*_swimbot.fit(_data(ds), args))


def audit(
    ds: Optional[Dataset] = None,
    preset: Optional[str] = None,
    effects: Sequence[str] = (),
    family_samples: Optional[int] = None,
    seed: Optional[int] = None,
) -> Audit:
    """``swimbot audit``: geometry consistency, ratio tests, influence, outliers."""
    args = _model_args(preset, effects, ())
    if family_samples is not None:
        args.append(_flag("family-samples", family_samples))
    if seed is not None:
        args.append(_flag("seed", seed))
    return Audit(_swimbot.audit(_data(ds), args))


#: Geometries in one ``sweep`` call: the CLI's ``sweep`` grid limit.
MAX_SWEEP_GEOMETRIES = 10_000_000


def _floats(name: str, value: Any):
    """``value`` as a float64 array; text, complex numbers, objects and
    booleans are refused naming the argument (numpy would turn "12" into
    12.0, None into NaN and drop an imaginary part)."""
    import numpy as np

    try:
        a = np.asarray(value)
    except Exception as e:  # a ragged list
        raise SwimbotError(f"sweep: {name}: not an array of numbers: {e}") from None
    if a.dtype.kind not in "fiu":
        raise SwimbotError(
            f"sweep: {name}: {a.dtype} values ({type(value).__name__}); give real numbers (float or int arrays)"
        )
    return a.astype(np.float64, copy=False)


def sweep(
    wavelength_mm: Any = None,
    amplitude_mm: Any = None,
    tail_length_mm: Any = None,
    frequency_hz: Any = None,
    *,
    data: Optional[Dataset] = None,
    case: Optional[str] = None,
    preset: Optional[str] = None,
    effects: Sequence[str] = (),
    study: Optional["Study"] = None,
):
    """The model's swimming speed U (mm/s) and body rotation rate Omega_b
    (Hz) over numpy arrays of geometries, broadcast together; a field not
    given is the template case's (``case`` of ``data``, default the
    paper's first case). With ``study``, the study's calibrated model
    (its preset and every step, located laws included) on the study's
    data (``data`` still overrides the template), as ``swimbot sweep``
    inside the study. Returns ``(u_mm_s, omega_body_hz)`` in the
    broadcast shape. Parallel, with the GIL released."""
    import numpy as np

    given = {
        "wavelength_mm": wavelength_mm,
        "amplitude_mm": amplitude_mm,
        "tail_length_mm": tail_length_mm,
        "frequency_hz": frequency_hz,
    }
    arrays = {k: _floats(k, v) for k, v in given.items() if v is not None}
    try:
        shape = np.broadcast_shapes(*(a.shape for a in arrays.values())) if arrays else ()
    except ValueError as e:
        shapes = ", ".join(f"{k} {a.shape}" for k, a in arrays.items())
        raise SwimbotError(f"sweep: the shapes do not broadcast together ({shapes}): {e}") from None
    n = int(math.prod(shape))
    # Refused before the broadcast arrays are made: 10^5 x 10^5 would be
    # 80 GB of each.
    if n > MAX_SWEEP_GEOMETRIES:
        raise SwimbotError(
            f"sweep: {n} geometries (shape {shape}); at most {MAX_SWEEP_GEOMETRIES} in one call, "
            "as the CLI's sweep: split it into several calls"
        )
    if data is not None and not isinstance(data, Dataset):
        raise SwimbotError(f"sweep: data must be a swimbot.Dataset (swimbot.load(path)), not {type(data).__name__}")
    columns = {
        k: np.ascontiguousarray(np.broadcast_to(a, shape)).ravel().tobytes()
        for k, a in arrays.items()
    }
    if study is not None and not isinstance(study, Study):
        raise SwimbotError(f"sweep: study must be a swimbot.Study (swimbot.Study.open(path)), not {type(study).__name__}")
    if study is not None and (preset is not None or _texts("effects", effects)):
        raise SwimbotError("sweep: study and preset/effects: give one or the other (the study's model is its preset with its steps)")
    template = data._inner if isinstance(data, Dataset) else None
    inner = study._inner if study is not None else None
    u, omega = _swimbot.sweep(
        n, _model_args(preset, effects, ()), template, case, study=inner, **columns
    )
    as_array = lambda b: np.frombuffer(b, dtype=np.float64).reshape(shape)
    return as_array(u), as_array(omega)


class Study:
    """A study (``swimbot-study.toml``): the model built step by step on one
    dataset, as ``swimbot init / add / undo / steps / report`` keep it. Each
    change is written to the file at once (atomically); two writers of one
    study never lose a step (the second is refused: open it again).

        s = swimbot.Study.init("swimbot-study.toml", "lab.csv")
        s.add("body-correction")
        s.steps()           # the whole study, as `swimbot steps --format json`
        s.report("report")  # the study's page
    """

    def __init__(self, inner: "_swimbot.Study"):
        self._inner = inner

    @classmethod
    def init(
        cls,
        path: Any,
        data: Any,
        preset: str = "base",
        likelihood: str = "gaussian",
        force: bool = False,
        diagnose: bool = True,
    ) -> "Study":
        """``swimbot init``: a new study at ``path`` on the dataset file ``data``."""
        return cls(_swimbot.study_init(_path("path", path), _path("data", data), _text("preset", preset),
                                       _text("likelihood", likelihood), _bool("force", force),
                                       _bool("diagnose", diagnose)))

    @classmethod
    def open(cls, path: Any = "swimbot-study.toml") -> "Study":
        """Open a study (its dataset checked against the pinned SHA-256)."""
        return cls(_swimbot.study_open(_path("path", path)))

    @property
    def path(self) -> str:
        return str(self._inner.path)

    @property
    def dataset(self) -> Dataset:
        return Dataset(self._inner.dataset)

    def steps(self) -> dict:
        """The whole study: ``swimbot steps --format json``."""
        return json.loads(self._inner.to_json())

    def add(self, effect: str, refit_all: bool = False, force: bool = False, diagnose: bool = True) -> dict:
        """``swimbot add``: a catalogue effect or ``FILE[#NAME]``; the new step."""
        if not isinstance(effect, (str, PathLike)):
            raise SwimbotError(f"effect: {effect!r} is neither a catalogue effect nor an effects file")
        effect = os.fspath(effect)
        return json.loads(self._inner.add(effect, _bool("refit_all", refit_all), _bool("force", force),
                                          _bool("diagnose", diagnose)))

    def undo(self) -> dict:
        """``swimbot undo``: removes the last step and returns it."""
        return json.loads(self._inner.undo())

    def apply_to(self, ds: Dataset) -> dict:
        """``swimbot steps --data``: the study's models on other data, parameters held."""
        if ds is None:
            raise SwimbotError("ds: give the Dataset (or its file) to apply the study to")
        return json.loads(self._inner.apply_to(_data(ds)))

    def report(self, directory: Any = "swimbot-out/report") -> str:
        """``swimbot report``: the study's page written to ``directory``; its path."""
        return str(self._inner.report(_path("directory", directory)))

    def sweep(self, **kwargs):
        """:func:`sweep` of this study's calibrated model on its data's
        setup (``case`` picks the case; keywords as :func:`sweep`'s)."""
        return sweep(study=self, **kwargs)

    def summary(self) -> list:
        """The study's headline, as ``swimbot steps`` opens: the start, then
        each step with its MARE before -> after in percent, then what
        ``diagnose`` says now. One dict a row: ``what``, ``mare_percent``
        (after), ``mare_before_percent`` (steps only), ``chi2_reduced``."""
        f = self.steps()
        start = f["start"]["stats"]
        rows = [{"what": f"start ({f['model']['preset']})", "mare_percent": 100.0 * start["mare"],
                 "chi2_reduced": start.get("chi2_reduced")}]
        for i, st in enumerate(f.get("step", []), 1):
            after = st["after"]["stats"]
            rows.append({"what": f"step {i} {st['effect']['name']}",
                         "mare_before_percent": 100.0 * st["before"]["mare"],
                         "mare_percent": 100.0 * after["mare"], "chi2_reduced": after.get("chi2_reduced")})
        steps = f.get("step", [])
        last = steps[-1].get("diagnosis_after") if steps else f.get("first_diagnosis")
        if last:
            rows.append({"what": f"diagnose now: {last['verdict']}"})
        return rows

    def _repr_html_(self) -> str:
        cells = []
        for r in self.summary():
            if "mare_percent" not in r:
                cells.append(f"<tr><td colspan='2'>{html.escape(r['what'])}</td></tr>")
                continue
            before = r.get("mare_before_percent")
            arrow = f"{before:.2f} % &rarr; " if before is not None else ""
            cells.append(f"<tr><td>{html.escape(r['what'])}</td><td>MARE {arrow}{r['mare_percent']:.2f} %</td></tr>")
        return f"<p>study {html.escape(self.path)}</p><table>{''.join(cells)}</table>"

    def __repr__(self) -> str:
        return repr(self._inner)
