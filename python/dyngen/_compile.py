"""dyngen.compile: a robot's generated code, built as its C library (docs/c-library.md) and
loaded, cached by a hash of the description, the choices and dyngen's version."""

import hashlib
import json
import os
import shutil
import subprocess
from pathlib import Path

from . import _dyngen
from ._compiled import CompiledRobot
from ._dyngen import CompileError, Robot

#: The environment variable that overrides the cache directory.
CACHE_VARIABLE = "DYNGEN_CACHE_DIR"


def cache_directory():
    """Where compiled robots are kept: $DYNGEN_CACHE_DIR, else $XDG_CACHE_HOME/dyngen, else
    ~/.cache/dyngen. One cargo target directory inside it is shared by every robot, so the
    runtime and nalgebra compile once."""
    if os.environ.get(CACHE_VARIABLE):
        return Path(os.environ[CACHE_VARIABLE])
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "dyngen"


def _cargo():
    cargo = os.environ.get("CARGO") or shutil.which("cargo")
    if cargo is None:
        home = Path(os.environ.get("CARGO_HOME", Path.home() / ".cargo"))
        candidate = home / "bin" / "cargo"
        cargo = str(candidate) if candidate.is_file() else None
    if cargo is None:
        raise CompileError(
            "dyngen.compile needs a Rust toolchain to build the robot's generated code, and no "
            "`cargo` was found (on PATH, in $CARGO or in ~/.cargo/bin): install one with rustup "
            "(https://rustup.rs), or use the generic dynamics of dyngen.Robot, which need none"
        )
    return cargo


class _Lock:
    """An exclusive lock on a file, so that two processes do not build into one directory at
    once (POSIX; elsewhere nothing is locked)."""

    def __init__(self, path):
        self.path = path

    def __enter__(self):
        self.file = open(self.path, "w")
        try:
            import fcntl

            fcntl.flock(self.file, fcntl.LOCK_EX)
        except ImportError:
            pass
        return self

    def __exit__(self, *exc):
        self.file.close()


def _key(robot, functions, opt_level):
    path, yaml, sources, fingerprint = _dyngen.compile_source(robot, functions)
    digest = hashlib.sha256()
    digest.update(fingerprint.encode())
    digest.update(f"opt_level {opt_level}\n".encode())
    for source in sources:
        digest.update(str(source).encode())
        digest.update(Path(source).read_bytes())
    if yaml is not None:
        digest.update(yaml.encode())
    return digest.hexdigest(), yaml


def _build(cargo, crate, target, opt_level):
    environment = dict(os.environ)
    if opt_level is not None:
        environment["CARGO_PROFILE_RELEASE_OPT_LEVEL"] = str(opt_level)
    command = [
        cargo, "build", "--release", "--lib", "--message-format=json-render-diagnostics",
        "--manifest-path", str(crate / "Cargo.toml"), "--target-dir", str(target),
    ]
    try:
        run = subprocess.run(command, env=environment, capture_output=True, text=True)
    except OSError as e:
        raise CompileError(f"cannot run {cargo}: {e}") from None
    if run.returncode != 0:
        tail = "\n".join(run.stderr.strip().splitlines()[-30:])
        raise CompileError(f"building {crate} failed (cargo exit status {run.returncode}):\n{tail}")
    for line in run.stdout.splitlines():
        message = json.loads(line) if line.startswith("{") else {}
        if message.get("reason") == "compiler-artifact" and "cdylib" in message["target"]["kind"]:
            for name in message["filenames"]:
                if name.endswith((".so", ".dylib", ".dll")):
                    return Path(name)
    raise CompileError(f"building {crate}: cargo reported no shared library")


def compile(robot, *, functions=None, opt_level=None, cache_dir=None, rebuild=False, **load_options):
    """The robot's generated code, compiled and loaded: an object with the methods of
    dyngen.Robot, evaluated by the generated functions.

    `robot` is a description path (loaded with `load_options`, those of Robot.load) or a
    dyngen.Robot (loaded from a file, or made in memory such as Identification.robot).
    `functions`: the groups to generate besides kinematics and dynamics (a list of
    "regressors", "base_parameters", "forward_dynamics", "derivatives", "frames", or "all";
    default: every group up to 12 joints). `opt_level`: the optimisation level of the build
    (default: cargo's release, 3). The library is kept in the cache (`cache_directory()`)
    under a hash of the description's files, the choices, the functions, the optimisation
    level and dyngen's version, and built again only when one of them changes (or `rebuild`).
    Needs a cargo toolchain; raises CompileError otherwise, or when the build fails.
    """
    if isinstance(robot, (str, os.PathLike)):
        robot = Robot.load(robot, **load_options)
    elif load_options:
        raise TypeError("loading options are for a description path, not a loaded Robot")
    if opt_level is not None and opt_level not in (0, 1, 2, 3, "s", "z"):
        raise ValueError(f"opt_level: expected 0, 1, 2, 3, 's' or 'z', found {opt_level!r}")
    key, yaml = _key(robot, functions, opt_level)
    root = Path(cache_dir) if cache_dir is not None else cache_directory()
    entry = root / "robots" / f"{robot.name}-{key[:16]}"
    prefix = f"dyngen_{key[:16]}"
    library = entry / f"{prefix}{_suffix()}"
    if library.is_file() and not rebuild:
        return CompiledRobot(_dyngen.Library(library, prefix), robot)
    cargo = _cargo()
    entry.mkdir(parents=True, exist_ok=True)
    with _Lock(root / "build.lock"):
        if not library.is_file() or rebuild:
            description = None
            if yaml is not None:
                description = entry / f"{robot.name}.yaml"
                description.write_text(yaml)
            runtime = os.environ.get("DYNGEN_RUNTIME_PATH") or _dyngen.runtime_checkout()
            crate = entry / "crate"
            _dyngen.write_c_library(robot, crate, prefix, functions, description, runtime)
            built = _build(cargo, crate, root / "target", opt_level)
            partial = library.with_suffix(".partial")
            shutil.copyfile(built, partial)
            os.replace(partial, library)
    return CompiledRobot(_dyngen.Library(library, prefix), robot)


def _suffix():
    import sys

    if sys.platform == "darwin":
        return ".dylib"
    if sys.platform == "win32":
        return ".dll"
    return ".so"
