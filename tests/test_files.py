"""vslsp/files.py, the edge every reader of a user's file goes through: regular files only, the
size limit applied while reading, names the file system holds, npz headers before loading."""

from __future__ import annotations

import os
import stat

import numpy as np
import pytest

from vslsp.errors import InputError
from vslsp.files import check_name, load_npz, read_bytes, read_json, regular_file, shown


def test_the_limit_holds_while_reading_not_only_on_stat():
    # /proc files are regular files whose stat says 0 bytes: only the bounded read sees their length.
    path = "/proc/self/maps"
    if not os.path.exists(path) or os.stat(path).st_size != 0:
        pytest.skip("no /proc with zero-sized regular files here")
    assert stat.S_ISREG(regular_file(path).st_mode)
    with pytest.raises(InputError, match="is larger than 10 bytes"):
        read_bytes(path, "file", 10)


def test_special_files_are_refused_by_their_stat(tmp_path):
    os.mkfifo(tmp_path / "fifo")
    kinds = ((tmp_path / "fifo", r"a FIFO \(named pipe\)"), ("/dev/zero", "a character device"), (tmp_path, "a folder"))
    for path, kind in kinds:
        with pytest.raises(InputError, match=f"it is {kind}, not a regular file"):
            read_bytes(path, "file", 100)


def test_names_are_shown_and_checked_as_bytes(tmp_path):
    name = tmp_path / os.fsdecode(b"a\xff")
    assert shown(name).endswith("a\\xff")
    check_name(tmp_path / ("x" * 255))
    with pytest.raises(InputError, match="256 bytes long"):
        check_name(tmp_path / ("x" * 256))
    with pytest.raises(InputError, match="256 bytes long"):  # bytes, not characters: 128 two-byte letters
        check_name(tmp_path / ("é" * 128))


def test_json_depth_and_digits_are_bounded_before_parsing(tmp_path):
    path = tmp_path / "x.json"
    path.write_text("[" * 65 + "]" * 65)
    with pytest.raises(InputError, match="nests deeper than 64"):
        read_json(path, "file", 1000)
    path.write_text('["[[[[[[", 1]')  # brackets inside strings do not count
    assert read_json(path, "file", 1000) == ["[[[[[[", 1]


def test_npz_arrays_load_within_their_limit_and_objects_never(tmp_path):
    np.savez(tmp_path / "ok.npz", a=np.arange(10.0))
    assert load_npz(tmp_path / "ok.npz", "test data", 1000)["a"].sum() == 45
    with pytest.raises(InputError, match="declare 80 bytes, .* nothing was loaded"):
        load_npz(tmp_path / "ok.npz", "test data", 79, file_limit=10**6)
    np.savez(tmp_path / "objects.npz", a=np.array([{"x": 1}], dtype=object))
    with pytest.raises(InputError, match="holds pickled Python objects"):
        load_npz(tmp_path / "objects.npz", "test data", 10**6)
