"""Fitting the 1990 PTFE friction model to bearing tests, and discovering missing effects."""

from ._damper import read_friction_damper_json as read_friction_damper_json
