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

__all__ = [
    "CompileError",
    "DescriptionError",
    "DyngenError",
    "Excitation",
    "IdentificationError",
    "Identification",
    "Payload",
    "Robot",
    "__version__",
    "excite",
    "identify",
    "identify_payload",
]
