"""Reading and writing trajkit's files."""

from trajkit.io.atomic import atomic_write

__all__ = ["atomic_write"]
