"""Home Assistant fixtures for the TecoApi (tecomat) vendor."""
