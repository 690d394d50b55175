"""Each controller's firmware semantics on the shared machine: one package a controller."""
