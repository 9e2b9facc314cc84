"""Home Assistant fixtures for the S7 (ISO-on-TCP) vendor."""
