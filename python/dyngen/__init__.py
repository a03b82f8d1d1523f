"""dyngen for Python: robot descriptions, their rigid-body dynamics on numpy batches, robots
compiled to generated code, and identification from arrays. See docs/python.md."""

from ._dyngen import (
    CompileError,
    DescriptionError,
    DyngenError,
    Excitation,
    IdentificationError,
    Identification,
    Payload,
    Robot,
    __version__,
    excite,
    identify,
    identify_payload,
)
from ._compile import cache_directory, compile
from ._compiled import CompiledRobot

__all__ = [
    "CompileError",
    "CompiledRobot",
    "DescriptionError",
    "DyngenError",
    "Excitation",
    "IdentificationError",
    "Identification",
    "Payload",
    "Robot",
    "__version__",
    "cache_directory",
    "compile",
    "excite",
    "identify",
    "identify_payload",
]
