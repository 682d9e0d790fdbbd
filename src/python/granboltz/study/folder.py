"""The folder of a parameter study (granboltz.study): its parts checked to be its own (no
symbolic link among them), files written atomically only when they change, whatever is in the
way moved aside to damaged/, and the runner lock (one runner per study folder)."""

import contextlib
import fcntl
import itertools
import os
import pathlib
import stat
import tempfile

from .safe_yaml import StudyError, file_kind, lstat


_PARTS = ("points", "runs", "logs", "damaged", ".snakemake")


def check_folder(folder):
    """StudyError unless the study folder (if it exists) is a folder whose parts (points/, runs/,
    logs/, damaged/, .snakemake/ and everything in .snakemake/) are its own: folders and files,
    never a symbolic link, so nothing written in it lands elsewhere."""
    st = lstat(folder)
    if st is None:
        return
    try:
        st = os.stat(folder)  # the study folder itself may be a link (to a scratch disk, say)
    except OSError as e:
        raise StudyError(f"{folder}: the study folder cannot be used ({e.strerror or e})") from None
    if not stat.S_ISDIR(st.st_mode):
        raise StudyError(f"{folder}: the study folder is {file_kind(st.st_mode)}, not a folder")
    for part in _PARTS:
        st = lstat(folder / part)
        if st is not None and not stat.S_ISDIR(st.st_mode):
            raise StudyError(f"{folder / part}: is {file_kind(st.st_mode)}, not a folder of the study "
                             "(move it away; the study makes its own)")
    for root, dirs, files in os.walk(folder / ".snakemake"):
        for name in dirs + files:
            st = lstat(os.path.join(root, name))
            if st is not None and not (stat.S_ISDIR(st.st_mode) or stat.S_ISREG(st.st_mode)):
                raise StudyError(f"{os.path.join(root, name)}: is {file_kind(st.st_mode)} inside Snakemake's folder "
                                 "(move it away)")


def move_aside(path, folder):
    """Move `path` (a file, folder, link or FIFO of the study folder, never followed) into
    damaged/ under a fresh name; returns the new path."""
    aside = folder / "damaged"
    aside.mkdir(exist_ok=True)
    stem = str(path.relative_to(folder)).replace(os.sep, "-")
    for n in itertools.count():
        target = aside / (stem if n == 0 else f"{stem}.{n}")
        if lstat(target) is None:
            break
    try:
        os.rename(path, target)
    except OSError as e:
        raise StudyError(f"{path}: cannot move it aside to {target} ({e.strerror or e})") from None
    return target


def write_if_changed(path, text, folder=None):
    """Write `text` to `path` (atomically) only when the file does not already hold it. Whatever
    is at `path` and is not a regular file (a link, folder, FIFO) is moved to damaged/ first."""
    path = pathlib.Path(path)
    folder = pathlib.Path(folder) if folder is not None else path.parent
    data = text.encode()
    st = lstat(path)
    if st is not None and stat.S_ISREG(st.st_mode):
        try:
            fd = os.open(path, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK | os.O_CLOEXEC)
            with os.fdopen(fd, "rb") as f:
                if f.read(len(data) + 1) == data:
                    return False
        except OSError:
            pass
    elif st is not None:
        move_aside(path, folder)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise
    return True


LOCK_NAME = ".runner.lock"


@contextlib.contextmanager
def runner_lock(folder):
    """Hold the study folder's runner lock: flock on the folder itself, so that no file deleted
    or planted inside it (a FIFO or a new file in place of .runner.lock) can let a second runner
    in; .runner.lock holds the runner's pid for the message. Yields the lock's file descriptor,
    to be inherited by Snakemake so that the lock lives as long as the runner or its Snakemake
    does, or None where the file system has no flock. StudyError when another runner holds it."""
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / LOCK_NAME
    try:
        lock = os.open(folder, os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC)
    except OSError as e:
        raise StudyError(f"{folder}: cannot open the study folder ({e.strerror or e})") from None
    try:
        try:
            fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
            held = True
        except BlockingIOError:
            pid = _read_pid(path)
            raise StudyError(f"{folder}: another `granboltz.study run` of this study, or the Snakemake it "
                             f"started, is running{' (runner pid ' + pid + ')' if pid else ''}; "
                             "wait for it or stop it (SIGTERM)") from None
        except OSError:  # no flock here (some network file systems): no stale-lock recovery either
            held = False
        if held:
            _write_pid(path, folder)
        yield lock if held else None
    finally:
        os.close(lock)


def _read_pid(path):
    """The pid in .runner.lock if it is a regular file that holds one, else ""."""
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK | os.O_CLOEXEC)
    except OSError:
        return ""
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            return ""
        words = os.pread(fd, 40, 0).decode(errors="replace").split()
    finally:
        os.close(fd)
    return words[0] if words and words[0].isdigit() else ""


def _write_pid(path, folder):
    """Write this runner's pid to .runner.lock (with the folder's lock held): anything but a
    regular file there is moved aside to damaged/ first, and a link is never followed."""
    st = lstat(path)
    if st is not None and not stat.S_ISREG(st.st_mode):
        move_aside(path, folder)
    try:
        fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_NOFOLLOW | os.O_NONBLOCK | os.O_CLOEXEC, 0o644)
    except OSError as e:
        raise StudyError(f"{path}: cannot open the runner lock ({e.strerror or e})") from None
    try:
        os.ftruncate(fd, 0)
        os.pwrite(fd, f"{os.getpid()}\n".encode(), 0)
    finally:
        os.close(fd)
