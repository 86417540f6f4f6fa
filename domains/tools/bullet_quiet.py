"""Silencing bullet's C++ output, for the tools that load robots into pybullet."""

import contextlib
import ctypes
import os
import sys

libc = ctypes.CDLL(None)


@contextlib.contextmanager
def quiet_stdout():
    """Silences what bullet's C++ prints (a warning per link without inertial data)."""
    sys.stdout.flush()
    saved = os.dup(1)
    with open(os.devnull, "w") as null:
        os.dup2(null.fileno(), 1)
        try:
            yield
        finally:
            libc.fflush(None)  # bullet's printf buffers; flush it into /dev/null, not later
            os.dup2(saved, 1)
            os.close(saved)
