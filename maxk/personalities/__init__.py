"""Personalities: each controller's firmware semantics, free of any wire format."""
