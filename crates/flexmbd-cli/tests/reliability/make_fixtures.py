#!/usr/bin/env python3
"""Write the `.dat` inputs of the reliability tests that are made from flexmbd's own fixtures.

The fuzzing campaign of 2026-12-01 found these defects with inputs derived from SPACAR files of
public repositories that state no licence (crates/flexmbd-io/tests/models/README.md, "Left out").
Those inputs are not copied; the files below show the same defects and are made from flexmbd's
own fixtures in crates/flexmbd-io/tests/models (MIT OR Apache-2.0), byte for byte by this
script (run it in this folder).
"""
import os

HERE = os.path.dirname(os.path.abspath(__file__))
MODELS = os.path.join(HERE, "..", "..", "..", "flexmbd-io", "tests", "models")


def read(name):
    with open(os.path.join(MODELS, name), "rb") as f:
        return f.read()


def write(folder, data, name="in.dat"):
    os.makedirs(os.path.join(HERE, folder), exist_ok=True)
    with open(os.path.join(HERE, folder, name), "wb") as f:
        f.write(data)


strip = read("strip_end_moment.dat")
cantilever = read("cantilever_light07.dat")

# `convert a.dat a.dat` destroyed its input: any valid model shows it
write("manual_dataloss_convert_same_path", strip)

# control characters in comments were copied into TOML comments, which TOML forbids
lines = strip.split(b"\n")
lines[0] = b"#Title with ctrl \x1b char"
lines[1] = lines[1] + b" \x00 \x0b \x0c \x7f"
lines[7] = lines[7].replace(b"#node 2", b"#node\x1b[31m 2")
write("manual_convert_unreadable_output", b"\n".join(lines))

# old-Mac CR line ends (the whole file was one comment, copied with its control characters into
# the TOML) and a vertical tab between two fields of a data line and in a comment
lines = strip.split(b"\n")
lines[2] = lines[2] + b" \x0c"
lines[8] = lines[8].replace(b"\t", b"\x0b", 1)
write("roundtrip_convert_534cf4800f", b"\r".join(lines))

# a coordinate of -1e308: the .dat and its conversion both fail numerically (exit 1), alike
write("roundtrip_convert_c8b8047827",
      cantilever.replace(b"0.600000\t0.000000", b"0.600000\t-1e308", 1))
