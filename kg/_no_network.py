"""Forbid this process to open Internet sockets, for good: the query worker's second wall.

The sandbox refuses ``SERVICE`` before a query runs; should anything slip through, Oxigraph's
HTTP client still needs a socket. :func:`forbid_network` installs a seccomp filter that makes
``socket(AF_INET | AF_INET6, ...)`` fail with ``EACCES`` in this process and every thread and
child it starts; Unix sockets (the worker's pipe to the server) keep working. A seccomp filter
cannot be removed, and it needs no privilege (``no_new_privs`` is set first).
"""

import ctypes
import errno
import platform
import socket
import struct

__all__ = ["forbid_network"]

_PR_SET_NO_NEW_PRIVS = 38
_PR_SET_SECCOMP = 22
_SECCOMP_MODE_FILTER = 2
_RET_ALLOW = 0x7FFF0000
_RET_ERRNO = 0x00050000
_X32_BIT = 0x40000000

# (audit architecture, number of the socket system call) per machine
_ARCHES = {
    "x86_64": (0xC000003E, 41),
    "aarch64": (0xC00000B7, 198),
}

# classic BPF opcodes
_LD_W_ABS = 0x20
_JEQ_K = 0x15
_RET_K = 0x06


class _Filter(ctypes.Structure):
    _fields_ = [
        ("code", ctypes.c_ushort),
        ("jt", ctypes.c_ubyte),
        ("jf", ctypes.c_ubyte),
        ("k", ctypes.c_uint),
    ]


class _Program(ctypes.Structure):
    _fields_ = [("len", ctypes.c_ushort), ("filter", ctypes.POINTER(_Filter))]


def _program(arch: int, socket_nr: int) -> list[tuple[int, int, int, int]]:
    deny = _RET_ERRNO | errno.EACCES
    return [
        (_LD_W_ABS, 0, 0, 4),  # seccomp_data.arch
        (_JEQ_K, 1, 0, arch),
        (_RET_K, 0, 0, deny),  # a foreign ABI: refuse everything rather than guess
        (_LD_W_ABS, 0, 0, 0),  # seccomp_data.nr
        (_JEQ_K, 2, 0, socket_nr),
        (_JEQ_K, 1, 0, socket_nr | _X32_BIT),
        (_RET_K, 0, 0, _RET_ALLOW),
        (_LD_W_ABS, 0, 0, 16),  # seccomp_data.args[0], low word: the address family
        (_JEQ_K, 2, 0, socket.AF_INET),
        (_JEQ_K, 1, 0, socket.AF_INET6),
        (_RET_K, 0, 0, _RET_ALLOW),
        (_RET_K, 0, 0, deny),
    ]


def forbid_network() -> None:
    """Make every later ``socket(AF_INET / AF_INET6)`` in this process fail with EACCES.

    Raises ``OSError`` if the kernel refuses the filter and ``NotImplementedError`` on a machine
    whose system call numbers are not known here.
    """
    machine = platform.machine()
    if machine not in _ARCHES or struct.calcsize("P") != 8:
        raise NotImplementedError(f"no seccomp network filter for machine {machine!r}")
    instructions = _program(*_ARCHES[machine])
    filters = (_Filter * len(instructions))(*(_Filter(*i) for i in instructions))
    program = _Program(len(instructions), filters)
    libc = ctypes.CDLL(None, use_errno=True)
    ulong = ctypes.c_ulong
    libc.prctl.argtypes = [ctypes.c_int, ulong, ctypes.c_void_p, ulong, ulong]
    if libc.prctl(_PR_SET_NO_NEW_PRIVS, 1, None, 0, 0) != 0:
        raise OSError(ctypes.get_errno(), "prctl(PR_SET_NO_NEW_PRIVS) failed")
    if libc.prctl(_PR_SET_SECCOMP, _SECCOMP_MODE_FILTER, ctypes.addressof(program), 0, 0) != 0:
        raise OSError(ctypes.get_errno(), "prctl(PR_SET_SECCOMP) failed")
