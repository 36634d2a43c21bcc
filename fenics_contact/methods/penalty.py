"""Penalty: ``F = K <g>``."""
from ..laws import Penalty
from .spec import Method, Parameter, Sweep

__all__ = ["METHOD"]

METHOD = Method(
    name="penalty", summary="penalty, F = K <g>", law=Penalty,
    parameters=(Parameter("K", "K", "penalty K (pressure per length)"),),
    self_contact="fenics_contact.methods.builders:law_self",
    friction="law", sweep=Sweep("wide", "K", colour="tab:blue", size=11.0))
