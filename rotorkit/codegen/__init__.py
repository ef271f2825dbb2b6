"""Code generation: turn derived equations into a fast right-hand side."""
