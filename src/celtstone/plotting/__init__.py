"""Figures from celtstone results; the only package that imports matplotlib, lazily."""
