"""Benchmarks run as modules: ``python -m f16mmae.benchmarks.lcm_latency``."""
