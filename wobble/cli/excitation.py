"""``wobble excitation``: the geodetic excitation of polar motion from the IERS record (Liouville equation)."""

from __future__ import annotations

import argparse

from wobble.cli._record import add_outputs, add_record, report
from wobble.errors import InputError

EPILOG = """\
examples:
  wobble excitation                                 the whole IERS 20 C04 record
  wobble excitation --start 1990 --end 2020 --json
  wobble excitation -o chi.nc --plot chi.png --overwrite
  wobble excitation --q 100 --period 433d --file finals2000A.all

The excitation chi = chi_1 + i chi_2 drives the pole p = x_p - i y_p through the
Liouville equation p + (i/sigma_c) dp/dt = chi, sigma_c = 2 pi/T_c (1 + i/(2Q))
(Munk & MacDonald 1960; Gross 1992; Brzezinski 1992), inverted exactly for daily
data with chi constant over each day (Wilson 1985's filter without its small-step
approximation). Running it forward rebuilds the record (round_trip_rms_mas). T_c is
wobble's least-squares period of the record and Q that of its Chandler budget
(anelastic Love number) unless given. Amplitudes in milliarcseconds (mas).
"""


def register(sub) -> None:
    p = sub.add_parser(
        "excitation",
        help="geodetic excitation of polar motion (inverse Liouville equation) and its round trip",
        description="The geodetic excitation chi(t) of the IERS polar-motion record by the exact discrete Liouville "
        "equation with the complex Chandler frequency, the pole rebuilt from it, its spectrum (broadband at the "
        "Chandler frequency) and the Chandler band before and after 2015.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_record(p)
    p.add_argument(
        "--period", metavar="T", help="Chandler period T_c, e.g. 433d (default: wobble's estimate from the record)"
    )
    p.add_argument(
        "--q", metavar="Q", help="quality factor Q > 0, or inf (default: wobble's Chandler budget, about 82)"
    )
    add_outputs(
        p,
        output_help="write pole, excitation, round trip, band amplitudes and spectra (CF-1.10 netCDF)",
        plot_help="write a figure: spectra of pole and excitation, the Chandler band against time",
    )
    p.set_defaults(func=run)


def parse_q(text):
    """--q as a float (inf allowed); None when not given."""
    if text is None:
        return None
    try:
        value = float(text)
    except ValueError:
        raise InputError("--q", text, "a quality factor Q > 0, e.g. 100, or inf") from None
    if not value > 0:
        raise InputError("--q", text, "a quality factor Q > 0, e.g. 100, or inf")
    return value


def parse_days(text, name):
    """A time such as 433d, 365 d or 1 yr as a Quantity (a bare number is days); None when not given."""
    if text is None:
        return None
    from astropy import units as u

    raw = str(text).strip()
    try:
        value = float(raw)
        return value * u.day
    except ValueError:
        pass
    try:
        q = u.Quantity(raw)
    except (ValueError, TypeError):
        raise InputError(name, text, "a time such as 365d, 8 yr or a number of days") from None
    if q.unit.physical_type != "time":
        raise InputError(name, text, "a time such as 365d, 8 yr or a number of days")
    return q


def run(args) -> int:
    from wobble.api.polar_motion.excitation import geodetic_excitation
    from wobble.cli._output import check_outputs

    q = parse_q(args.q)
    period = parse_days(args.period, "--period")
    check_outputs(args)
    ex = geodetic_excitation(args.file, start=args.start, end=args.end, chandler_period=period, q=q)
    return report(args, ex, "wobble.plot.excitation:save_excitation_figure")
