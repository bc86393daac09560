"""Command-line options shared by every command that builds a model or reads a measurement."""

from __future__ import annotations

import argparse


def add_model_options(p: argparse.ArgumentParser, mesh_default: str = "default", mesh_help: str = "mesh resolution",
                      effects_help: str = "+name,-name to change the default set (write --effects=-name when it "
                                          "starts with -), or a,b,c for an exact set") -> None:
    """--effects, --set, --mesh, --seed."""
    p.add_argument("--effects", help=effects_help)
    p.add_argument("--set", action="append", default=[], metavar="EFFECT.PARAM=VALUE",
                   help="set a parameter with its unit, e.g. spindle_motor.power=120W (repeatable)")
    p.add_argument("--mesh", default=mesh_default, choices=["coarse", "default", "fine"],
                   help=f"{mesh_help} (default {mesh_default})")
    p.add_argument("--seed", type=int, default=0, help="seed of the instrument noise")
    p.add_argument("--effects-file", metavar="FILE",
                   help="TOML file of effects the library lacks (twin.effects.custom): simulate and compare switch "
                        "them on, diagnose offers them as candidates")


def add_measurement_options(p: argparse.ArgumentParser) -> None:
    """MEASUREMENT, --mapping, --machine, --scenario."""
    p.add_argument("measurement", help="a twin NetCDF result, or a CSV file with a TOML column mapping")
    p.add_argument("--mapping", help="TOML column mapping of a CSV (default: the CSV's name with .toml)")
    p.add_argument("--machine", help="the measured machine (default: the one the measurement names: a result's "
                                     "'machine' attribute or the mapping's machine key)")
    p.add_argument("--scenario", help="drive the twin by this scenario instead of the measured inputs")
