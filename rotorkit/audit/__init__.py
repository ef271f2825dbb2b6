"""API 617 audit of a rotor: formulas, checks, shear and moment, the HTML report."""
