"""Reading users' logs: one in-memory :class:`Log` from RTKLIB ``.pos``, PX4 ULog, ROS bags
(when present), NMEA and CSV files, and :func:`read`, which picks the reader from the file.

Every reader converts to quatnav's conventions at the boundary: body frame forward-right-down,
navigation frame NED, quaternions Hamilton [w, x, y, z] ``q_nb``, SI units, radians, times in
seconds. A file that cannot be read, or lacks what is asked of it, raises ``ValueError`` with one
line naming the file and what is missing.
"""
from __future__ import annotations

import os
from pathlib import Path

from .log import Baro, Compass, Gnss, Imu, Log, Mag, Reference, mag_on_imu_times

__all__ = ["Log", "Imu", "Mag", "Gnss", "Baro", "Compass", "Reference", "read", "FORMATS", "detect",
           "mag_on_imu_times"]

#: format name -> what it reads
FORMATS = {"rtklib": "RTKLIB .pos solution", "ulog": "PX4 ULog (pyulog)", "nmea": "NMEA 0183 GGA/RMC/VTG",
           "csv": "CSV with named columns", "rosbag": "ROS 1 .bag / ROS 2 bag folder (rosbags)",
           "parquet": "Parquet with the named columns of a CSV (pyarrow): the output of ins run, ahrs run"}


def detect(path) -> str:
    """The format of ``path`` from its content (first bytes), then its extension."""
    p = Path(path)
    if p.is_dir():
        if (p / "metadata.yaml").exists():
            return "rosbag"
        raise ValueError(f"{path}: a folder that is not a ROS 2 bag (no metadata.yaml)")
    with open(p, "rb") as fh:
        head = fh.read(4096)
    from .ulog import looks_like_ulog
    if looks_like_ulog(head):
        return "ulog"
    if head.startswith(b"PAR1"):
        return "parquet"
    if head.startswith(b"#ROSBAG V2.0"):
        return "rosbag"
    ext = p.suffix.lower()
    if head.startswith(b"MATLAB"):  # the text header of every MAT-file, v4 excepted ("MATLAB 5.0 MAT-file")
        raise ValueError(f"{path}: a MATLAB MAT-file, not a format read here ({', '.join(FORMATS)}): load it "
                         "with scipy.io.loadmat (the BROAD trials and NaveGo's run: quatnav.datasets)")
    if b"\x00" in head and ext not in (".ulg", ".bag", ".mcap", ".db3"):
        raise ValueError(f"{path}: cannot tell the format: binary content (not UTF-8 text), and none of the "
                         f"binary formats read here (ULog, ROS bag)")
    text = head.decode("utf-8", errors="replace")
    from .nmea import looks_like_nmea
    from .rtklib import looks_like_pos
    if looks_like_pos(text):
        return "rtklib"
    if looks_like_nmea(text):
        return "nmea"
    by_ext = {".pos": "rtklib", ".ulg": "ulog", ".nmea": "nmea", ".gps": "nmea", ".csv": "csv", ".txt": "csv",
              ".bag": "rosbag", ".mcap": "rosbag", ".db3": "rosbag", ".parquet": "parquet"}
    if ext in by_ext:
        return by_ext[ext]
    if "," in text or ";" in text:
        return "csv"
    raise ValueError(f"{path}: cannot tell the format (use format=: {', '.join(FORMATS)})")


def read(path, format: str = "auto", **options) -> Log:
    """Read a log file into a :class:`Log`.

    Parameters
    ----------
    path : str or Path
        The file (a ROS 2 bag: its folder).
    format : {"auto", "rtklib", "ulog", "nmea", "csv", "rosbag"}
        "auto" detects it from the content, then the extension.
    **options
        Passed to the reader (e.g. ``imu_topic=`` for bags, ``mag_topic=`` for ULog, ``kind=`` for CSV).

    Raises
    ------
    ValueError
        The file cannot be read in that format (one line naming the file and the problem).
    FileNotFoundError
        No such file.
    """
    if not os.path.exists(path):
        raise FileNotFoundError(f"{path}: no such file")
    fmt = detect(path) if format == "auto" else format
    if fmt in ("rtklib", "pos"):
        from .rtklib import read_pos
        return read_pos(path, **options)
    if fmt == "ulog":
        from .ulog import read_ulog
        return read_ulog(path, **options)
    if fmt == "nmea":
        from .nmea import read_nmea
        return read_nmea(path, **options)
    if fmt == "csv":
        from .csvfile import read_csv
        from .table import CsvError
        try:
            return read_csv(path, **options)
        except CsvError as e:
            raise ValueError(str(e)) from None
    if fmt == "parquet":
        return _read_parquet(path, **options)
    if fmt == "rosbag":
        try:
            from .rosbag import read_bag
        except ImportError as e:  # pragma: no cover - depends on what is installed
            raise ValueError(f"{path}: reading ROS bags is not available ({e})") from None
        return read_bag(path, **options)
    raise ValueError(f"{path}: unknown format {fmt!r} (known: {', '.join(FORMATS)})")


def _read_parquet(path, kind=None) -> Log:
    """A Parquet file of named columns, read as the CSV of the same columns would be."""
    import tempfile
    try:
        import pandas as pd
        df = pd.read_parquet(path)
    except ImportError:
        raise ValueError(f"{path}: reading Parquet needs pandas and pyarrow: pip install 'quatnav[logs]'") from None
    from .csvfile import read_csv
    from .table import CsvError
    with tempfile.TemporaryDirectory() as d:
        p = os.path.join(d, "table.csv")
        df.to_csv(p, index=False, float_format="%.17g")
        try:
            log = read_csv(p, kind=kind)
        except CsvError as e:
            raise ValueError(str(e).replace(p, str(path))) from None
    log.source, log.format = str(path), "parquet"
    return log
