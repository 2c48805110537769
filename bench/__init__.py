"""Benchmarks that print figures (not tests); run each as `python -m bench.<name>`."""
