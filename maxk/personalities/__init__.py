"""Controller personalities: each controller's firmware semantics, below its language."""
