"""The `sodaevo` command of a pip install: the program CMake built, installed
inside the package (sodaevo/bin/sodaevo), run with the arguments given."""
from __future__ import annotations

import os
import sys
from pathlib import Path


def program() -> Path:
    """Where the installed `sodaevo` program is."""
    return Path(__file__).resolve().parent / "bin" / "sodaevo"


def main() -> None:
    path = program()
    if not path.is_file():
        sys.exit(f"sodaevo: {path} is missing (this package was not installed by pip; build the command with CMake)")
    os.execv(path, [str(path), *sys.argv[1:]])
