"""Fretting cycles: waveform load histories, Q-delta loops, slip amplitude, dissipated energy
and the running regime."""

from .cycles import CycleResult, FrettingAnalysis, analyse
from .waveform import SHAPES, Waveform

__all__ = ["SHAPES", "CycleResult", "FrettingAnalysis", "Waveform", "analyse"]
