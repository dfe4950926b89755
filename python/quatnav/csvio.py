"""Reading numeric CSV logs with named columns: :func:`read_table`.

One reader for every command that takes CSV (``quatnav ins run``, ...), built on pandas' C
parser (``pip install 'quatnav[io]'``; the rest of quatnav needs numpy only):

* a header row of column names, in any order; names are matched without regard to case or
  surrounding spaces (``" Gyro_X "`` is ``gyro_x``); extra columns are ignored;
* the delimiter is sniffed from the header line: ``,``, ``;``, tab, or runs of spaces; with
  ``;`` or tab a decimal comma (``9,81``) is recognised;
* UTF-8 with or without a byte-order mark; blank lines and lines starting with ``#`` are skipped
  (before and after the header);
* required columns must hold a finite number in every row; optional columns may be absent (all
  NaN) or empty in a row (NaN);
* errors are :class:`CsvError` (a ``ValueError``) whose message names the file, the line number
  *in the file* (1-based, counting skipped lines) and the column.
"""
from __future__ import annotations

import io
import re
from dataclasses import dataclass, field

import numpy as np

__all__ = ["CsvError", "Table", "read_table", "sniff_delimiter", "normalize_name"]

_DELIMS = (",", ";", "\t")
_DECIMAL_COMMA = re.compile(r"^\s*[-+]?\d+,\d*([eE][-+]?\d+)?\s*$")


class CsvError(ValueError):
    """A problem with a CSV file; the message is a one-line report (file, line, column)."""


@dataclass
class Table:
    """Columns of a CSV file as float arrays, with the file line of every row.

    Attributes
    ----------
    path : str
    columns : dict of str -> (N,) float ndarray
        Every required and optional column (optional ones absent from the file are all NaN).
    lines : (N,) int ndarray
        Line number in the file (1-based) of each row.
    header : list of str
        The file's column names, normalized (lower case, stripped).
    delimiter : str
    decimal : str
    """

    path: str
    columns: dict
    lines: np.ndarray
    header: list = field(default_factory=list)
    delimiter: str = ","
    decimal: str = "."
    what: str = "file"

    def __getitem__(self, name: str) -> np.ndarray:
        return self.columns[name]

    def __contains__(self, name: str) -> bool:
        return name in self.columns

    def __len__(self) -> int:
        return len(self.lines)

    def stack(self, names) -> np.ndarray:
        """(N, len(names)) array of the named columns."""
        return np.column_stack([self.columns[n] for n in names])

    def where(self, row: int) -> str:
        """``"IMU imu.csv: line 12"`` for row ``row`` (for messages)."""
        return f"{self.what} {self.path}: line {int(self.lines[row])}"


def normalize_name(name: str) -> str:
    """Column name as matched: stripped of spaces and quotes, lower case."""
    return name.strip().strip('"').strip("'").strip().lower()


def sniff_delimiter(header_line: str) -> str:
    """The delimiter of a header line: the most frequent of ``,`` ``;`` tab, else whitespace
    (``r"\\s+"``) when the line has several words, else ``,``."""
    counts = {d: header_line.count(d) for d in _DELIMS}
    best = max(_DELIMS, key=lambda d: counts[d])
    if counts[best] > 0:
        return best
    return r"\s+" if len(header_line.split()) > 1 else ","


def _fmt(x) -> str:
    return repr(float(x)) if np.isfinite(x) else str(float(x))


def read_table(path, required, optional=(), what: str = "file", increasing: str | None = "time",
               min_rows: int = 1) -> Table:
    """Read a CSV file with a header row into float columns.

    Parameters
    ----------
    path : str or Path
        The file.
    required : sequence of str
        Columns that must be present with a finite number in every row (lower-case names).
    optional : sequence of str
        Columns that may be absent or empty (NaN).
    what : str
        What the file is, for messages (``"IMU"``, ``"GNSS"``, ...).
    increasing : str or None
        A column (``"time"``) that must be strictly increasing; None: no check.
    min_rows : int
        Fewest data rows accepted.

    Returns
    -------
    Table

    Raises
    ------
    CsvError
        Naming the file, its line number and the column.
    ModuleNotFoundError
        Without pandas (``pip install 'quatnav[io]'``).
    """
    from ._optional import require
    pd = require("pandas", "reading CSV files")
    required, optional = tuple(required), tuple(optional)
    where = f"{what} {path}"
    try:
        with open(path, "r", encoding="utf-8-sig", newline="") as fh:
            text = fh.read()
    except UnicodeDecodeError as e:
        raise CsvError(f"{where}: not UTF-8 text (byte {e.start}); save it as UTF-8 CSV") from None
    except OSError as e:
        raise CsvError(f"{where}: cannot open ({e.strerror})") from None
    raw_lines = text.splitlines()
    keep = [i for i, ln in enumerate(raw_lines) if ln.strip() and not ln.lstrip().startswith("#")]
    if not keep:
        raise CsvError(f"{where}: empty file (no header row)")
    header_line = raw_lines[keep[0]]
    header_lineno = keep[0] + 1
    sep = sniff_delimiter(header_line)
    if sep == r"\s+":
        header = [normalize_name(c) for c in header_line.split()]
    else:
        header = [normalize_name(c) for c in next(iter(__import__("csv").reader([header_line], delimiter=sep)))]
    seen = set()
    for c in header:
        if c and c in seen:
            raise CsvError(f"{where}: line {header_lineno}: column {c!r} appears twice in the header")
        seen.add(c)
    missing = [c for c in required if c not in header]
    if missing:
        raise CsvError(f"{where}: line {header_lineno}: missing column {missing[0]!r} "
                       f"(needs {', '.join(required)}; found {', '.join(h for h in header if h)})")
    data_idx = keep[1:]
    if len(data_idx) < min_rows:
        raise CsvError(f"{where}: {'no data rows' if not data_idx else f'{len(data_idx)} data rows'}"
                       + (f" (needs at least {min_rows})" if data_idx else ""))
    lines = np.asarray(data_idx, dtype=np.int64) + 1
    body = [raw_lines[i] for i in data_idx]
    decimal = "."
    if sep in (";", "\t"):
        first = body[0].split(sep)
        if any(_DECIMAL_COMMA.match(c) for c in first) and not any("." in c for c in first):
            decimal = ","
    ncol = len(header)
    try:
        df = pd.read_csv(io.StringIO("\n".join(body)), sep=sep, header=None, names=list(range(ncol)),
                         keep_default_na=False, na_values=[""], decimal=decimal, skipinitialspace=True,
                         engine="c" if sep != r"\s+" else "python", dtype=None, index_col=False)
    except pd.errors.ParserError as e:
        m = re.search(r"Expected (\d+) fields in line (\d+), saw (\d+)", str(e))
        if m:
            k = int(m.group(2)) - 1
            ln = int(lines[k]) if 0 <= k < len(lines) else "?"
            raise CsvError(f"{where}: line {ln}: {m.group(3)} fields, the header (line {header_lineno}) "
                           f"has {m.group(1)}") from None
        raise CsvError(f"{where}: cannot parse ({' '.join(str(e).split())})") from None
    if len(df) != len(lines):  # pragma: no cover - quoted line breaks and the like
        raise CsvError(f"{where}: {len(df)} rows parsed from {len(lines)} lines (quoted line breaks?)")
    n = len(df)
    out = {}
    for c in required + optional:
        if c not in header:
            out[c] = np.full(n, np.nan)
            continue
        col = df[header.index(c)]
        empty = col.isna().to_numpy()
        if col.dtype.kind in "fiu":
            vals = col.to_numpy(dtype=np.float64)
            raw = None
        else:
            raw = col.astype(object).to_numpy()
            text = col.astype(object).map(lambda x: x.strip().replace(decimal, ".") if isinstance(x, str) else x)
            vals = pd.to_numeric(text, errors="coerce").to_numpy(dtype=np.float64)
        bad = ~empty & ~np.isfinite(vals)
        if c in required:
            bad |= empty
        if bad.any():
            i = int(np.argmax(bad))
            if empty[i]:
                nf = len(body[i].split()) if sep == r"\s+" else body[i].count(sep) + 1
                kind = f"empty (the line has {nf} fields, the header {ncol})" if nf < ncol else "empty"
            else:
                kind = f"not a finite number ({(str(raw[i]).strip() if raw is not None else _fmt(vals[i]))!r})"
            raise CsvError(f"{where}: line {int(lines[i])}, column {c!r}: {kind}")
        out[c] = vals
    if increasing is not None and increasing in out:
        t = out[increasing]
        d = np.diff(t)
        badk = np.flatnonzero(~(d > 0))
        if badk.size:
            k = int(badk[0]) + 1
            word = "duplicate time" if d[badk[0]] == 0 else "time goes backwards"
            raise CsvError(f"{where}: line {int(lines[k])}, column {increasing!r}: {word} ({_fmt(t[k])} after "
                           f"{_fmt(t[k - 1])} on line {int(lines[k - 1])}); times must be strictly increasing")
    return Table(path=str(path), columns=out, lines=lines, header=header, delimiter=sep, decimal=decimal,
                 what=what)
