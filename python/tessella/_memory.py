"""Memory that :func:`tessella.refine` reuses between calls.

The arrays ``refine`` returns own their memory as usual. When numpy frees the last array or
view of one, tessella keeps the memory (up to a limit, 2 GiB unless set) and the next call of
about the same size writes into it, instead of asking the system for fresh pages, which the
kernel must fault in and zero one 4 KiB page at a time. A loop of ``refine`` calls then runs
at the speed of writing into memory already in use. Memory an array or view still uses is
never handed out again.

New memory is advised to use transparent huge pages when numpy advises them for its own arrays
(its default on Linux), for results of 4 MiB or more.
"""

from . import _tessella
from ._errors import OptionError


def release_memory() -> int:
    """Frees the memory kept for reuse; returns how many bytes that was."""
    return int(_tessella._release_memory())


def set_memory_reuse(max_bytes: int) -> int:
    """Sets how many bytes of freed output arrays tessella keeps for later calls (``0``: none,
    and what is kept now is freed); returns the previous limit."""
    if max_bytes < 0:
        raise OptionError(f"max_bytes must be 0 or more, got {max_bytes}")
    return int(_tessella._set_memory_reuse(max_bytes))


def reusable_bytes() -> int:
    """Bytes of freed output arrays kept now, ready for the next call."""
    return int(_tessella._reusable_bytes())
