"""Atomic writes: the one mechanism every file the package writes goes through.

A file is written to a temporary file in its own folder (``.NAME.XXXX.tmp``), flushed to
disk (``fsync``) and moved over the target with ``os.replace``, so a reader (or a run
interrupted by Ctrl-C) sees either the previous complete file or the new complete one, never
a torn one; on an exception (KeyboardInterrupt included) the temporary file is removed.

:func:`staged` groups the writes of one result folder: inside the block every atomic write
goes to its temporary file only, and the block's end moves them all into place at once,
with SIGINT held back during the moves, so an interrupted run leaves the folder's previous
files (or none) and a finished one leaves all new files, never a mix of the two.

Test hook: the environment variable ``TRIBOBEM_TEST_PAUSE`` (tests only) makes a process
stop at a chosen point, after printing ``tribobem-test: pause ...`` on stderr, so that a
test can send a real SIGINT there: ``write:PATTERN[@N]=SECONDS`` pauses after the temporary
file of the N-th written file whose path matches the glob PATTERN is complete (before it is
moved into place); ``solve[@N]=SECONDS`` (see :mod:`tribobem.scenario.run`) in the N-th
solve, after its first step.  Entries are separated by commas.
"""

from __future__ import annotations

import contextvars
import fnmatch
import os
import signal
import sys
import tempfile
import threading
import time
from contextlib import contextmanager
from pathlib import Path

__all__ = ["atomic_path", "atomic_write_bytes", "atomic_write_text", "staged", "staged_source",
           "sigint_deferred"]

#: Glob of the temporary files (next to their targets).
TMP_GLOB = ".*.tmp"


def _default_mode() -> int:
    """Permissions of a new file under the current umask (mkstemp creates 0600 files)."""
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


def _unlink(path) -> None:
    try:
        os.unlink(path)
    except OSError:
        pass


@contextmanager
def sigint_deferred():
    """Hold SIGINT back inside the block: a Ctrl-C that arrives there is delivered (as
    KeyboardInterrupt, or whatever the previous handler does) when the block ends.  Outside
    the main thread (Dask workers' threads) signals cannot be handled and nothing changes."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    got = []
    try:
        old = signal.signal(signal.SIGINT, lambda signum, frame: got.append(signum))
    except (ValueError, OSError):  # pragma: no cover - no signal support here
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, old if old is not None else signal.SIG_DFL)
        if got:
            if callable(old):
                old(signal.SIGINT, sys._getframe())
            elif old in (None, signal.SIG_DFL):
                signal.raise_signal(signal.SIGINT)


def temp_path(path) -> str:
    """A new empty temporary file next to ``path`` (same folder, so ``os.replace`` is atomic),
    with ordinary permissions.

    Parameters
    ----------
    path : path-like
        The target file; its folder is created if needed.

    Returns
    -------
    str
        Path of the temporary file ``.NAME.XXXX.tmp`` (mode 0666 minus the umask, not
        mkstemp's 0600, so that the file keeps ordinary permissions once it replaces the target).
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = None
    try:
        with sigint_deferred():  # a Ctrl-C here cannot leave an unnamed temporary file
            fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
            os.close(fd)
            os.chmod(tmp, _default_mode())
    except BaseException:
        if tmp is not None:
            _unlink(tmp)
        raise
    return tmp


def _fsync(path) -> None:
    """Flush a written file to disk (before it replaces its target)."""
    try:
        fd = os.open(path, os.O_RDWR)
    except OSError:  # pragma: no cover - a read-only file
        fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


class _Stage:
    """Temporary files waiting to be moved into place together (see :func:`staged`)."""

    def __init__(self):
        self.pending: dict[str, str] = {}  # target -> temporary file, in the order written

    def add(self, path: str, tmp: str) -> None:
        old = self.pending.pop(path, None)  # the same file written twice: the last one wins
        if old is not None and old != tmp:
            _unlink(old)
        self.pending[path] = tmp

    def commit(self) -> None:
        with sigint_deferred():
            for path, tmp in list(self.pending.items()):
                os.replace(tmp, path)
                del self.pending[path]

    def discard(self) -> None:
        for tmp in self.pending.values():
            _unlink(tmp)
        self.pending.clear()


_STAGE: contextvars.ContextVar[_Stage | None] = contextvars.ContextVar("tribobem_atomic_stage", default=None)


def _key(path) -> str:
    return os.path.abspath(os.fspath(path))


@contextmanager
def staged():
    """Move every file written atomically inside the block into place together at its end.

    On an exception (KeyboardInterrupt included) nothing is moved and the temporary files are
    removed: the targets keep their previous content (or stay absent).  The moves themselves
    run with SIGINT held back, so a Ctrl-C cannot stop them half-way.  Nested blocks join the
    outermost one.  A file written in the block and read again in it is read through
    :func:`staged_source`.
    """
    if _STAGE.get() is not None:
        yield
        return
    stage = _Stage()
    token = _STAGE.set(stage)
    try:
        yield
        stage.commit()
    except BaseException:
        stage.discard()
        raise
    finally:
        _STAGE.reset(token)


def staged_source(path) -> Path:
    """Where the content of ``path`` is now: its temporary file while a :func:`staged` block
    holds it back, else ``path`` itself.

    Parameters
    ----------
    path : path-like
        A target file.

    Returns
    -------
    pathlib.Path
        The file to read.
    """
    stage = _STAGE.get()
    if stage is not None:
        tmp = stage.pending.get(_key(path))
        if tmp is not None:
            return Path(tmp)
    return Path(path)


@contextmanager
def atomic_path(path):
    """Yield a temporary path next to ``path``; when the block has written it, it is synced
    to disk and replaces ``path`` atomically (or, inside :func:`staged`, at the end of that
    block); on an exception it is removed.

    A reader therefore sees either the old file or the complete new one, never a partial
    write (an interrupted run leaves its previous outputs intact).

    Parameters
    ----------
    path : path-like
        The target file.

    Yields
    ------
    pathlib.Path
        The temporary file to write.
    """
    path = Path(path)
    tmp = temp_path(path)
    try:
        yield Path(tmp)
        _fsync(tmp)
        pause_hook("write", path)
        stage = _STAGE.get()
        if stage is not None:
            stage.add(_key(path), tmp)
        else:
            os.replace(tmp, path)
    except BaseException:
        _unlink(tmp)
        raise


def atomic_write_bytes(path, data: bytes) -> Path:
    """Write ``data`` to ``path`` via a temporary file in the same folder, fsync and
    ``os.replace`` (:func:`atomic_path`).

    Parameters
    ----------
    path : path-like
        The target file.
    data : bytes
        The content.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    with atomic_path(path) as tmp:
        with open(tmp, "wb") as fh:
            fh.write(data)
    return Path(path)


def atomic_write_text(path, text: str) -> Path:
    """UTF-8 text version of :func:`atomic_write_bytes` (no newline translation).

    Parameters
    ----------
    path : path-like
        The target file.
    text : str
        The content, written as UTF-8 as is (the same bytes on every platform).

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    return atomic_write_bytes(path, text.encode("utf-8"))


def file_state(path):
    """``(inode, mtime_ns, size)`` of ``path``, None when it does not exist.

    Two equal states mean the file was not replaced in between (``os.replace`` brings a new
    inode).

    Parameters
    ----------
    path : path-like
        Any file.

    Returns
    -------
    tuple of int or None
    """
    try:
        st = os.stat(path)
    except OSError:
        return None
    return (st.st_ino, st.st_mtime_ns, st.st_size)


# ----------------------------------------------------------------------------- test hook
_PAUSE_COUNTS: dict[str, int] = {}


def pause_hook(kind: str, path=None) -> None:
    """Tests only: pause where ``TRIBOBEM_TEST_PAUSE`` asks (see the module docstring).

    The pause gives a test the moment to send a real SIGINT at a known point of a write or
    a solve.  Without the variable it returns at once.

    Parameters
    ----------
    kind : str
        The pause point, ``"write"`` or ``"solve"``.
    path : path-like, optional
        The file being written, matched against the entry's pattern.
    """
    spec = os.environ.get("TRIBOBEM_TEST_PAUSE")
    if not spec:
        return
    for entry in spec.split(","):
        what, _, seconds = entry.strip().rpartition("=")
        what, _, nth = what.partition("@")
        name, _, pattern = what.partition(":")
        if name != kind or (pattern and (path is None or not fnmatch.fnmatch(Path(path).as_posix(), pattern))):
            continue
        _PAUSE_COUNTS[entry] = count = _PAUSE_COUNTS.get(entry, 0) + 1
        if count == int(nth or 1):
            print(f"tribobem-test: pause {kind}" + (f" {Path(path).name}" if path is not None else ""),
                  file=sys.stderr, flush=True)
            time.sleep(float(seconds))
