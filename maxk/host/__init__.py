"""Doors for legacy host code: real-time pacing, TCP and serial (MAXnet framing), the
pyserial URL handler and the PCI shared-memory map."""
