"""Measured figures of PLC Bridge, printed with the command that made them."""
