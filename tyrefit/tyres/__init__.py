"""Tyre containers: coefficients plus the design data a simulator needs, evaluated in SI and ISO-W."""

from .pac89 import Pac89Tyre

__all__ = ["Pac89Tyre"]
