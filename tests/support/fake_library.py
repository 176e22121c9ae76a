"""Stand-ins for librmw_introspect_cpp.so where a test only needs a file the middleware's
search accepts as a whole library (``run.middleware.library_damage``), never one to load."""

from __future__ import annotations

import struct


def elf_header(shoff: int = 64) -> bytes:
    """A 64-bit little-endian ELF header of a shared object whose section headers (3 of 64
    bytes) start at ``shoff``: with ``shoff`` 64 the file is whole at 256 bytes, with more it
    is truncated."""
    head = (b"\x7fELF\x02\x01\x01" + bytes(9)
            + struct.pack("<HHIQQQIHHHHHH", 3, 62, 1, 0, 64, shoff, 0, 64, 56, 0, 64, 3, 2))
    return head + bytes(max(0, 256 - len(head))) if shoff == 64 else head


#: what a test writes as a library it never loads
WHOLE = elf_header()
