"""The version of the package (one place; lemke.__version__ and `lemke --version` read it)."""
__version__ = "0.1.0"
