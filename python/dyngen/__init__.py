"""dyngen for Python: robot descriptions, their rigid-body dynamics on numpy batches, robots
compiled to generated code, and identification from arrays. See docs/python.md."""

from ._dyngen import (
    CompileError,
    DescriptionError,
    DyngenError,
    IdentificationError,
    Robot,
    __version__,
)

__all__ = [
    "CompileError",
    "DescriptionError",
    "DyngenError",
    "IdentificationError",
    "Robot",
    "__version__",
]
