"""Readers of the IERS C04 and finals2000A files: the shipped data, and broken files named by line."""

from __future__ import annotations

import numpy as np
import pytest

from wobble.errors import FileFormatError
from wobble.io.eop import default_c04_path, read_c04, read_finals2000a, read_pole_file

C04 = default_c04_path()
FINALS = C04.parent / "finals2000A.all"


def _c04_lines(n=40):
    lines = C04.read_text().splitlines()
    head = [ln for ln in lines[:20] if ln.startswith("#")]
    data = [ln for ln in lines if not ln.startswith("#")][:n]
    return head, data


def _write(tmp_path, lines, name="eop.txt"):
    path = tmp_path / name
    path.write_text("\n".join(lines) + "\n")
    return path


def test_shipped_c04_reads_whole_and_offline():
    rec = read_c04()
    assert rec.format == "c04" and "C04" in rec.title
    assert rec.mjd[0] == 37665.0  # 1962-01-01, the first line of the file
    assert np.all(np.diff(rec.mjd) == 1.0)  # daily, no gap
    # Values of the first data line, read by hand from the file (columns of ReadMe.eopc04).
    first = [ln for ln in C04.read_text().splitlines() if not ln.startswith("#")][0].split()
    assert rec.x[0] == float(first[5]) and rec.y[0] == float(first[6])
    assert rec.x_error[0] == float(first[13]) and rec.y_error[0] == float(first[14])
    assert len(rec.mjd) == sum(1 for ln in C04.read_text().splitlines() if ln.strip() and not ln.startswith("#"))
    assert 0.0 < np.median(rec.y) < 0.6 and np.all(np.abs(rec.x) < 1.0)


def test_finals_keeps_observed_rows_only():
    rec = read_pole_file(FINALS)
    assert rec.format == "finals2000A"
    lines = FINALS.read_text().splitlines()
    observed = [ln for ln in lines if len(ln) > 16 and ln[16] == "I"]
    assert len(rec.mjd) == len(observed)
    assert rec.mjd[-1] == float(observed[-1][7:15])
    # Column order in finals2000A is x, error, y, error.
    assert (rec.x[0], rec.x_error[0], rec.y[0], rec.y_error[0]) == (
        float(observed[0][18:27]),
        float(observed[0][27:36]),
        float(observed[0][37:46]),
        float(observed[0][46:55]),
    )
    # The two series agree to a few mas where they overlap (Bulletin A vs C04).
    c04 = read_c04()
    common, i, j = np.intersect1d(c04.mjd, rec.mjd, return_indices=True)
    assert common.size > 10000
    assert np.sqrt(np.mean((c04.x[i] - rec.x[j]) ** 2)) < 0.01  # arcsec


def test_truncated_c04_line_is_named(tmp_path):
    head, data = _c04_lines()
    data[10] = data[10][:100]
    path = _write(tmp_path, head + data)
    with pytest.raises(FileFormatError, match=rf"line {len(head) + 11}: truncated"):
        read_c04(path)


def test_truncated_last_line_is_not_a_shorter_series(tmp_path):
    head, data = _c04_lines()
    path = tmp_path / "cut.txt"
    path.write_text("\n".join(head + data) + "\n" + data[-1][:60])  # cut mid-line, no newline
    with pytest.raises(FileFormatError, match=rf"line {len(head) + len(data) + 1}: truncated"):
        read_pole_file(path)


def test_malformed_number_is_named(tmp_path):
    head, data = _c04_lines()
    line = data[5]
    data[5] = line[:26] + "  0.1x3456  " + line[38:]
    path = _write(tmp_path, head + data)
    with pytest.raises(FileFormatError, match=rf"line {len(head) + 6}: columns 27-38 \(x\) hold '0.1x3456'"):
        read_c04(path)


def test_nan_is_not_a_value(tmp_path):
    head, data = _c04_lines()
    line = data[3]
    data[3] = line[:38] + f"{'nan':>12}" + line[50:]
    with pytest.raises(FileFormatError, match=rf"line {len(head) + 4}: columns 39-50 \(y\)"):
        read_c04(_write(tmp_path, head + data))


def test_dates_must_increase(tmp_path):
    head, data = _c04_lines()
    data[7], data[8] = data[8], data[7]
    with pytest.raises(FileFormatError, match=rf"line {len(head) + 9}: MJD .* does not follow"):
        read_c04(_write(tmp_path, head + data))


def test_a_date_that_is_not_its_mjd_is_named(tmp_path):
    """An MJD damaged into another increasing value (the first line's 37665 made 30084, 1941) would pass as a
    gap of decades; each line's calendar date must be that of its MJD (fuzz run of 2026-11-28)."""
    head, data = _c04_lines()
    assert data[0].startswith("1962   1   1") and "37665.00" in data[0]
    moved = [data[0].replace("37665.00", "30084.00"), *data[1:]]
    with pytest.raises(
        FileFormatError,
        match=rf"line {len(head) + 1}: the date in columns 1-12 \('1962   1   1'\) is "
        r"not that of the MJD 30084.00 \(1941-03-31\)",
    ):
        read_c04(_write(tmp_path, head + moved))
    lines = [ln for ln in FINALS.read_text().splitlines() if ln.strip()][:20]
    assert lines[3].startswith("73 1 5") and lines[3][7:15] == "41687.00"
    lines[3] = lines[3][:7] + "41687.50" + lines[3][15:]  # the same day: accepted
    assert read_finals2000a(_write(tmp_path, lines, "f1")).mjd[3] == 41687.5
    lines[3] = lines[3][:4] + " 6" + lines[3][6:]
    with pytest.raises(
        FileFormatError,
        match=r"line 4: the date in columns 1-6 \('73 1 6'\) is not that of the MJD "
        r"41687.50 \(1973-01-05\)",
    ):
        read_pole_file(_write(tmp_path, lines, "f2"))


def test_finals_errors(tmp_path):
    lines = FINALS.read_text().splitlines()[:30]
    bad_flag = list(lines)
    bad_flag[4] = bad_flag[4][:16] + "X" + bad_flag[4][17:]
    with pytest.raises(FileFormatError, match="line 5: column 17 holds 'X'"):
        read_finals2000a(_write(tmp_path, bad_flag, "f1"))
    cut = list(lines)
    cut[12] = cut[12][:40]
    with pytest.raises(FileFormatError, match="line 13: truncated"):
        read_finals2000a(_write(tmp_path, cut, "f2"))
    junk = list(lines)
    junk[2] = junk[2][:18] + " 0.1?0733" + junk[2][27:]
    with pytest.raises(FileFormatError, match=r"line 3: columns 19-27 \(x\)"):
        read_pole_file(_write(tmp_path, junk, "f3"))
    predictions = [ln[:16] + "P" + ln[17:] for ln in lines]
    with pytest.raises(FileFormatError, match="no data lines"):
        read_finals2000a(_write(tmp_path, predictions, "f4"))


@pytest.mark.parametrize(
    ("content", "fragment"),
    [
        ("", "no data lines"),
        ("hello world\n", "line 1: neither the IERS C04"),
        ("# only a header\n\n", "no data lines"),
    ],
)
def test_unknown_or_empty_files(tmp_path, content, fragment):
    path = tmp_path / "x.txt"
    path.write_text(content)
    with pytest.raises(FileFormatError, match=fragment):
        read_pole_file(path)


def test_missing_and_binary_files(tmp_path):
    with pytest.raises(FileFormatError, match="no such file"):
        read_pole_file(tmp_path / "nope.txt")
    path = tmp_path / "bin.dat"
    path.write_bytes(b"\x00\xff\xfe" * 10)
    with pytest.raises(FileFormatError, match="not a text"):
        read_pole_file(path)


def test_shipped_files_are_found_by_name_from_any_folder(tmp_path, monkeypatch):
    from wobble.io.eop import resolve_eop_path

    monkeypatch.chdir(tmp_path)
    assert resolve_eop_path("finals2000A.all") == FINALS
    assert read_pole_file("eopc04.1962-now").mjd.size == read_c04().mjd.size
    # A file of that name in the working folder wins; a path with a folder is taken as given.
    (tmp_path / "finals2000A.all").write_text(FINALS.read_text()[:2000])
    assert resolve_eop_path("finals2000A.all").resolve() == (tmp_path / "finals2000A.all").resolve()
    assert str(resolve_eop_path("sub/finals2000A.all")) == "sub/finals2000A.all"
    with pytest.raises(FileFormatError, match="no such file .*finals2000A.all"):
        read_pole_file("sub/finals2000A.all")


def test_iso_date_is_the_calendar_date_without_erfa_warnings():
    """iso_date agrees with astropy's UTC date where ERFA has no complaint (1962-2026, every 97th day),
    and with Python's proleptic Gregorian calendar where ERFA warns of a "dubious year" (before 1960,
    after the leap-second table): a damaged or old file's dates print without a warning (fuzz run of
    2026-11-28; the tests turn warnings into errors)."""
    import datetime

    from astropy.time import Time

    from wobble.io.dates import iso_date

    mjd = np.arange(37665.0, 61000.0, 97.0) + 0.25
    assert [iso_date(m) for m in mjd] == [t[:10] for t in Time(mjd, format="mjd", scale="utc").iso]
    zero = datetime.date(1858, 11, 17).toordinal()
    for m in (-678575.0, 0.0, 30084.0, 36933.9, 80000.5, 2_000_000.0):
        assert iso_date(m) == datetime.date.fromordinal(zero + int(np.floor(m))).isoformat()
        assert iso_date(Time(m, format="mjd", scale="utc")) == iso_date(m)
    assert iso_date(1e300) == "MJD 1e+300" and iso_date(float("nan")) == "MJD nan"
