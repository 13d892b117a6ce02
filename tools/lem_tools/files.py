"""The one way result files are written: into a temporary name beside the
target, renamed over it only once complete, so that a reader (or a rerun
that checks what exists) never sees half a file."""
import contextlib
import json
import os


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
