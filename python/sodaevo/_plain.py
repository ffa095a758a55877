"""Values a config dict may hold that json cannot write: numpy numbers and arrays
(a loop's np.int64 frames, a np.float64 rate) become plain numbers and lists."""
from __future__ import annotations

from typing import Any


def plain_json_value(value: Any) -> Any:
    """json.dumps' `default`: numpy scalars and arrays as Python numbers and lists."""
    if hasattr(value, "tolist") and hasattr(value, "dtype"):
        return value.tolist()
    raise TypeError(f"Object of type {type(value).__name__} is not JSON serializable")
