"""Test support shared by the test modules and the benchmark scripts (not shipped)."""
