"""armplan: human-like arm movements for NAO (command line and launcher)."""

__version__ = "0.1.0"
