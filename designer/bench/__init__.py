"""Benchmarks run by ``designer bench NAME``; each prints a table of measured figures."""
