"""The one way result files are written: into a temporary name beside the
target, renamed over it only once complete, so that a reader (or a rerun
that checks what exists) never sees half a file; and the one check of a
folder a command is told to write into."""
import contextlib
import json
import os

from .errors import ToolError


@contextlib.contextmanager
def atomic_path(path):
    """Yield a temporary path beside `path`; rename it to `path` when the block
    ends normally, remove it when the block raises."""
    directory, name = os.path.split(path)
    # the pid keeps two processes writing the same file from sharing a name
    temporary = os.path.join(directory, ".%s.%d.part" % (name, os.getpid()))
    try:
        yield temporary
        os.replace(temporary, path)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.remove(temporary)
        raise


@contextlib.contextmanager
def atomic_open(path, mode="w", **open_args):
    """open() for writing whose file appears at `path` only when complete."""
    with atomic_path(path) as temporary:
        with open(temporary, mode, **open_args) as f:
            yield f


def write_json(path, data):
    with atomic_open(path) as f:
        json.dump(data, f, indent=2)


def require_folder_path(path, what, error=ToolError):
    """Raise `error` naming `what` (e.g. "the data folder (--data)") if
    `path`, or the nearest of its parents that exists, is a file: before
    any work, instead of os.makedirs' "[Errno 17] File exists"."""
    wanted = existing = os.path.abspath(path)
    while not os.path.exists(existing):
        existing = os.path.dirname(existing)
    if not os.path.isdir(existing):
        named = path if existing == wanted else "%s: %s" % (path, existing)
        raise error("%s %s is a file, not a folder: choose another path" % (what, named))
