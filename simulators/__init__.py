"""Faithful servers of each PLC vendor interface, for tests, the demo and the benchmarks."""
