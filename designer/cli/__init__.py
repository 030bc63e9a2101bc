"""The ``designer`` command line: thin wrappers around plain functions."""
