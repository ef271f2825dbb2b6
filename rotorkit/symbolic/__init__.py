"""Symbolic layer: safe piecewise functions and Lagrange's equations from element terms."""
