"""Normal compliance: ``F = c_n <g>^m_n``."""
from ..laws import NormalCompliance
from .spec import Method, Parameter, Sweep

__all__ = ["METHOD"]

METHOD = Method(
    name="compliance", summary="normal compliance, F = c_n <g>^m_n", law=NormalCompliance,
    parameters=(Parameter("c_n", "c_n", "c_n in F = c_n <g>^m_n (pressure per length^m_n; default: --K)",
                          default="K"),
                Parameter("m_n", "m_n", "exponent m_n >= 1", "exponent", 1.0)),
    self_contact="fenics_contact.methods.builders:law_self",
    friction="law", sweep=Sweep("narrow", "K"))
