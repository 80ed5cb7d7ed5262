"""One line naming the interpreter, the numerical stack and the CPU, so a failure says where it happened.

Run by .ci/run after each environment is installed, and shown in the header of every pytest run
(tests/conftest.py).
"""

import platform
import sys
from importlib import metadata

PACKAGES = ("numpy", "scipy", "numba", "llvmlite", "vtk", "pyvista", "matplotlib")


def cpu_model() -> str:
    """The CPU model as /proc/cpuinfo names it, else what platform knows."""
    try:
        with open("/proc/cpuinfo", encoding="utf-8", errors="replace") as f:
            for line in f:
                if line.lower().startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def version_line() -> str:
    """``Python 3.11.7, numpy 2.2.0, ..., CPU <model>``."""
    parts = [f"Python {platform.python_version()}"]
    for name in PACKAGES:
        try:
            parts.append(f"{name} {metadata.version(name)}")
        except metadata.PackageNotFoundError:
            parts.append(f"{name} (absent)")
    return ", ".join(parts) + f"; CPU {cpu_model()} ({sys.platform})"


if __name__ == "__main__":
    print(version_line(), flush=True)
