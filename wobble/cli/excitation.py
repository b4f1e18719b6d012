"""``wobble excitation``: the geodetic excitation of polar motion from the IERS record (Liouville equation)."""

from __future__ import annotations

import argparse

from wobble.cli._record import add_outputs, add_record, as_typed, check_file, parse_q, parse_time, report

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
approximation). Running it forward rebuilds the record (round_trip_rms_mas).
T_c is wobble's least-squares period of the whole record in --file unless given,
also when --start/--end choose a part of it: the period is the Earth's, and a few
years measure it poorly (the output says which span it comes from). A given T_c
(--period; a bare number is days) must lie from 136 d to 1217 d: a frequency of
0.3 to 2.7 cycles per year, so that the Chandler band and the neighbourhood its
peak is compared with lie inside the 3 cycles per year of the spectra, clear of
the mean pole at zero frequency (the daily record itself resolves down to 2 d).
Q is that of wobble's Chandler budget (anelastic Love number) unless given, at
least 1 (the free wobble decays by exp(-pi/Q) a cycle) or inf. The span must be
two years or more. Amplitudes in milliarcseconds (mas).
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
        "--period",
        metavar="T",
        help="Chandler period T_c, from 136 d to 1217 d, e.g. 433d or 433 (a bare number is days; default: "
        "wobble's least-squares period of the whole record, also for a part of it chosen by --start/--end)",
    )
    p.add_argument(
        "--q",
        metavar="Q",
        help="quality factor Q >= 1, or inf (undamped) (default: wobble's Chandler budget, about 82)",
    )
    add_outputs(
        p,
        output_help="write pole, excitation, round trip, band amplitudes and spectra (CF-1.10 netCDF)",
        plot_help="write a figure: spectra of pole and excitation, the Chandler band against time",
    )
    p.set_defaults(func=run)


def run(args) -> int:
    from wobble.api.polar_motion.excitation import geodetic_excitation
    from wobble.cli._output import check_outputs

    q = parse_q(args.q)
    period = parse_time(args.period, "--period", "d")
    check_outputs(args)
    check_file(args)
    options = {
        "chandler_period": ("--period", period and period.shown),
        "start/end": ("--start/--end", None),
    }
    with as_typed(options):
        ex = geodetic_excitation(
            args.file, start=args.start, end=args.end, chandler_period=period and period.quantity, q=q
        )
    return report(args, ex, "wobble.plot.excitation:save_excitation_figure")
