"""Tests of PLC Bridge."""
