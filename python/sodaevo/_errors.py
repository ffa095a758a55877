"""sodaevo.InputError: bad input, with where it is.

The engine's messages start with where the problem is: ``file:line:column: ...``
for XML and JSON syntax, ``file: /json/pointer: ...`` for a config value. The
exception keeps the message whole and also splits that place into fields.
"""
from __future__ import annotations

import re
from typing import Optional

_AT_LINE = re.compile(r"^(?P<file>[^\n]*?):(?P<line>\d+):(?P<column>\d+): ")
_AT_POINTER = re.compile(r"^(?P<file>[^\n:]*): (?P<pointer>/[^\s:]*): ")
_AT_FILE = re.compile(r"^(?P<file>[^\n:]+): ")


class InputError(ValueError):
    """Bad input: a model, race, config or argument the engine refuses.

    ``str(error)`` is the engine's complete message. ``file``, ``line``,
    ``column`` and ``pointer`` (a JSON pointer into a config) are the parts of
    the place it names, or None where the message has none.
    """

    file: Optional[str]
    line: Optional[int]
    column: Optional[int]
    pointer: Optional[str]

    def __init__(self, message: str) -> None:
        super().__init__(message)
        self.file = self.line = self.column = self.pointer = None
        first = message.splitlines()[0] if message else ""
        m = _AT_LINE.match(first)
        if m:
            self.file, self.line, self.column = m["file"], int(m["line"]), int(m["column"])
            return
        m = _AT_POINTER.match(first)
        if m:
            self.file, self.pointer = m["file"], m["pointer"]
            return
        m = _AT_FILE.match(first)
        if m and ("/" in m["file"] or "." in m["file"] or m["file"].startswith("<")):
            self.file = m["file"]
