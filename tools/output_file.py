"""How the Python tools write a file, as io::OutputFile does in C++
(dynamics/include/gimbalsim/io/output_file.hpp): into a temporary beside the
name, renamed onto it only when whole; an existing symbolic link or
non-regular file under the name is refused (OSError naming it)."""
import contextlib
import os
import stat


@contextlib.contextmanager
def output_path(path):
    """Yields a temporary path (same directory and extension) to write; on
    leaving without an exception it becomes `path`, else it is removed."""
    path = os.fspath(path)
    try:
        st = os.lstat(path)
    except FileNotFoundError:
        st = None
    if st is not None and stat.S_ISLNK(st.st_mode):
        raise OSError(f"{path}: is a symbolic link; not written through (give its target)")
    if st is not None and not stat.S_ISREG(st.st_mode):
        raise OSError(f"{path}: exists and is not a regular file; not written")
    head, name = os.path.split(path)
    stem, ext = os.path.splitext(name)
    tmp = os.path.join(head, f".{stem}.{os.getpid()}.tmp{ext}")
    try:
        yield tmp
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


def savefig(fig, path, **kwargs):
    """fig.savefig(path, ...) through output_path."""
    with output_path(path) as tmp:
        fig.savefig(tmp, **kwargs)
