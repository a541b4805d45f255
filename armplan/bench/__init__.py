"""Benchmarks behind ``armplan bench``: each beside a peer measured in the same run."""
