"""Reading and writing trajkit's files."""

from trajkit.io.atomic import StagedFiles, atomic_write, staged_files

__all__ = ["StagedFiles", "atomic_write", "staged_files"]
