"""The studio's one way to a file: a path relative to the root, refused when it leaves the root.

Refused (:class:`Outside`, HTTP 403): absolute paths, any ``..`` part (``%2e%2e`` arrives decoded
as ``..``), a NUL byte, backslashes, and any path whose resolved target (symlinks followed) is not
under the resolved root. A path inside that does not exist is :class:`Missing` (HTTP 404).
"""

from __future__ import annotations

import os
from pathlib import Path, PurePosixPath
from urllib.parse import unquote

from vslsp.errors import InputError

#: The largest upload the studio takes (bytes): an image, a predicates or PDDL file.
MAX_UPLOAD_BYTES = 32 * 1024 * 1024
#: The largest PDDL or plan text a request may carry (characters).
MAX_TEXT_CHARS = 2 * 1024 * 1024
#: Folders a listing does not walk into.
SKIPPED = frozenset({"__pycache__", "node_modules", "venv", "build", "dist"})


class Outside(InputError):
    """A path that would leave the root (HTTP 403)."""


class Missing(InputError):
    """A path under the root that does not exist (HTTP 404)."""


class Conflict(InputError):
    """A save over a file the request has not seen as it is now (HTTP 409)."""


def version_of(path: Path) -> str | None:
    """The version of a file's content (a hash of its bytes), None when there is no file."""
    import hashlib

    try:
        return hashlib.sha256(path.read_bytes()).hexdigest()
    except OSError:
        return None


def refuse_unseen(root: Path, rel: str, base: str | None) -> None:
    """:class:`Conflict` when ``rel`` exists and is not the version ``base`` (what the page read): a save
    never writes over a file nobody opened, or one changed on disk since, unless told to overwrite."""
    now = version_of(inside(root, rel, must_exist=False))
    if now is None or now == base:
        return
    if base is None:
        raise Conflict(f'{rel} exists and was not opened: open it first (its version), or send "overwrite": true')
    raise Conflict(f'{rel} changed on disk since it was opened: open it again, or send "overwrite": true')


def inside(root: Path, rel: str, *, must_exist: bool = True) -> Path:
    """The file ``rel`` names under ``root`` (resolved), or :class:`Outside` / :class:`Missing`."""
    if not isinstance(rel, str) or not rel.strip():
        raise InputError("give a path relative to the studio's root")
    if "\x00" in rel or "\\" in rel:
        raise Outside(f"{rel!r}: not a path under the studio's root")
    if len(rel.encode("utf-8", "surrogateescape")) > 4096 or any(
        len(part.encode("utf-8", "surrogateescape")) > 255 for part in rel.split("/")
    ):
        raise InputError("the path is too long: a name has at most 255 bytes and a path at most 4096")
    pure = PurePosixPath(rel)
    decoded = PurePosixPath(unquote(unquote(rel)))  # an encoded '..' (%2e%2e, %252e%252e) is refused too
    if pure.is_absolute() or ".." in (*pure.parts, *decoded.parts) or rel.startswith("~"):
        raise Outside(f"{rel}: outside the studio's root; give a path relative to it without '..'")
    base = root.resolve()
    target = (base / pure).resolve()
    if target != base and not target.is_relative_to(base):
        raise Outside(f"{rel}: leads outside the studio's root (a link out of it)")
    if must_exist and not target.exists():
        raise Missing(f"{rel}: no such file under the studio's root")
    return target


def relative(root: Path, path: Path) -> str:
    """``path`` (under ``root``) as the POSIX path relative to the root."""
    return path.resolve().relative_to(root.resolve()).as_posix()


def read_small(root: Path, rel: str, limit: int = MAX_TEXT_CHARS) -> str:
    """The UTF-8 text of a file under the root, at most ``limit`` bytes."""
    path = inside(root, rel)
    if not path.is_file():
        raise InputError(f"{rel}: not a file")
    if path.stat().st_size > limit:
        raise InputError(f"{rel}: larger than {limit // 1024} KiB; the studio edits smaller files")
    try:
        return path.read_bytes().decode("utf-8-sig")
    except UnicodeDecodeError:
        raise InputError(f"{rel}: not UTF-8 text; save it as UTF-8") from None


#: The kinds of file the studio writes (a PDDL domain or problem, a plan, notes).
WRITABLE = (".pddl", ".plan", ".txt")


def write_text(root: Path, rel: str, text: str, *, code: bool = False) -> Path:
    """Write ``text`` to ``rel`` under the root (folders under the root created), replacing the file whole.

    Only :data:`WRITABLE` kinds, and ``.py`` with ``code`` (the predicates editor of a studio started with
    ``--edit-code``); never into a hidden folder or a hidden file (``.venv/``, ``.git/``, ``.bashrc``), where a
    file would change what Python or a tool runs."""
    kinds = (*WRITABLE, ".py") if code else WRITABLE
    if not isinstance(rel, str) or not rel.endswith(kinds):
        more = "" if code else " (Python files only with vslsp studio --edit-code)"
        raise InputError(f"the studio saves {', '.join(kinds)} files{more}; {str(rel)[:200]!r} is none")
    if any(part.startswith(".") for part in PurePosixPath(rel).parts):
        raise InputError(f"{rel}: the studio never writes into hidden files or folders")
    if len(text) > MAX_TEXT_CHARS:
        raise InputError(f"{rel}: the text is over {MAX_TEXT_CHARS // 1024} KiB; the studio saves smaller files")
    path = inside(root, rel, must_exist=False)
    if path.is_dir():
        raise InputError(f"{rel}: is a folder; give a file name")
    if path.exists() and not path.is_file():
        raise InputError(f"{rel}: not a regular file; give a file name")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        from vslsp.outputs import write_text as write_whole

        write_whole(path, text)
    except OSError as error:
        raise InputError(f"{rel}: cannot write the file ({error.strerror})") from None
    return path


def listing(root: Path, suffixes: tuple[str, ...], limit: int = 500) -> list[str]:
    """Files under the root with one of ``suffixes`` (relative, sorted; hidden and virtualenv folders skipped,
    links not followed)."""
    base = root.resolve()
    found: list[str] = []
    for folder, folders, names in os.walk(base):
        folders[:] = sorted(f for f in folders if not f.startswith(".") and f not in SKIPPED)
        for name in sorted(names):
            path = Path(folder) / name
            if path.suffix.lower() in suffixes and not path.is_symlink():
                found.append(path.relative_to(base).as_posix())
                if len(found) >= limit:
                    return found
    return found
