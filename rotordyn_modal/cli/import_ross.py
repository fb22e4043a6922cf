"""``import-ross ROSS.toml --out MODEL.toml``: a rotor saved by ROSS as a model file."""

from __future__ import annotations

import sys

from ..errors import InputError
from ._common import add_input_file, add_output_file, check_ending
from ._units import STAYS_SI

NAME = "import-ross"
HELP = "read a rotor saved by ROSS (Rotor.save, TOML) into a model file"
UNITS_HELP = (STAYS_SI.split(" whatever")[0] + ": the model file it writes is SI, as every model file "
              "(docs/units.md)")   # --units
DESCRIPTION = """Read a rotor that ROSS saved with Rotor.save (a TOML file; ROSS need not be
installed) and write it as a model file with one flexible rotor: one shaft section per ROSS
shaft element (parallel elements as layers), its disks and its bearings and seals (constant
or tabulated over speed, ROSS's rad/s written as rpm). ROSS's x, y, z are the model's axes
(spin about +z, the shaft from the origin); kxy and kyx keep their signs. What this package
does not model is refused by name with exit code 2: point masses (support masses), magnetic
bearings, bearing mass coefficients, proportional or modal damping, elements without rotary
inertia or gyroscopic terms, axial force or torque, mixed shear options (docs/ross.md). A rotor
that is no valid model (a length, density or disk mass <= 0, a negative bearing coefficient,
bearings that leave it free) is refused the same way: no file is written that `check` refuses.

example:
  rotordyn-modal import-ross compressor.toml --out compressor_model.toml
  rotordyn-modal check compressor_model.toml"""


def add_arguments(parser):
    add_input_file(parser, "ross_file", metavar="ROSS.toml", help="rotor file written by ROSS's Rotor.save")
    add_output_file(parser, "--out", required=True, metavar="MODEL.toml",
                    help="model file to write ('-': standard output)")
    parser.add_argument("--name", help="the rotor's name (default: the ROSS file's stem, as ROSS saves no name of the rotor; "
                        "'rotor' for a file read from a pipe)")
    parser.add_argument("--quiet", action="store_true", help="no summary line on stderr")


def run(args) -> int:
    from ..io.ross_file import (DEFAULT_NAME, check_description, model_text, read_ross_rotor, without_name,
                                write_model_file)

    check_ending(args.out, (".toml",), "--out")
    if args.name is not None and not args.name.strip():   # a script's empty variable: was the file's stem
        raise InputError(f"--name {args.name!r}: expected the rotor's name (a text other than blanks)")
    description = read_ross_rotor(args.ross_file, name=args.name)
    check_description(description, args.ross_file)   # no model file that `check` would refuse
    if args.out == "-":
        sys.stdout.write(model_text(description))
    else:
        write_model_file(description, args.out, inputs=[args.ross_file])
    rotor = description["rotors"][0]
    if args.name is None and without_name(args.ross_file):   # was the rotor '63' of /dev/fd/63
        shown = getattr(args, "shown_names", {}).get(args.ross_file)   # '-': "standard input"
        source = f"{shown} gives no file's name" if shown else f"{args.ross_file} is a pipe, whose name is no file's"
        print(f"{NAME}: {source}: the rotor is named "
              f"{DEFAULT_NAME!r} (give --name NAME to name it)", file=sys.stderr)
    if not args.quiet:
        print(f"{args.out}: rotor {rotor['name']!r}, {len(rotor['shaft'])} shaft sections, "
              f"{len(rotor.get('disks', []))} disks, {len(description['bearings'])} bearings", file=sys.stderr)
    return 0
