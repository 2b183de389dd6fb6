"""The files the language server knows: the open documents (the editor's live text) and the PDDL files
beside them on disk, and how they belong together (a problem names its domain with ``(:domain NAME)``;
a plan belongs to the problems and domains of its folder)."""

from __future__ import annotations

import os
import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path

from pygls.uris import from_fs_path, to_fs_path

DOMAIN = "domain"
PROBLEM = "problem"
PLAN = "plan"
#: The extensions of plan files (``vslsp plan --out``, VAL's and IPC planners' outputs).
PLAN_SUFFIXES = (".plan", ".soln", ".sol")

_COMMENT = re.compile(r";[^\n]*")
_DEFINE = re.compile(r"\(\s*define\s*\(\s*(domain|problem)\s+([^\s()]+)", re.IGNORECASE)
_DOMAIN_OF = re.compile(r"\(\s*:domain\s+([^\s()]+)", re.IGNORECASE)
#: A problem's own choice of its domain file, as the VS Code PDDL extension reads it: ``;; !domain: FILE``
#: (FILE relative to the problem's folder).
CHOSEN = re.compile(r"^[ \t]*;+[ \t]*!domain:[ \t]*(\S+)", re.IGNORECASE | re.MULTILINE)
#: The folder's files larger than this are not read to find a domain or a domain's problems: a large problem
#: is not loaded only for its header (a document the editor opens is read whatever its size; the files
#: vslsp reads from disk have their own limit, vslsp.symbolic.language.files.MAX_PDDL_BYTES).
_LARGEST = 1_000_000


@dataclass(frozen=True)
class Header:
    """What a file is: ``kind`` domain, problem, plan or "" (not yet either); ``name`` its
    ``(domain NAME)``/``(problem NAME)``; ``domain`` the domain a problem names."""

    kind: str
    name: str = ""
    domain: str = ""


def read_header(uri: str, text: str) -> Header:
    """The header of ``text`` (comments ignored); a file with a plan extension is a plan."""
    if uri.lower().endswith(PLAN_SUFFIXES):
        return Header(PLAN)
    code = _COMMENT.sub("", text[:4096] if len(text) > 4096 else text)
    found = _DEFINE.search(code)
    if found is None:
        return Header("")
    kind, name = found.group(1).lower(), found.group(2)
    if kind == DOMAIN:
        return Header(DOMAIN, name)
    of = _DOMAIN_OF.search(code, found.end())
    return Header(PROBLEM, name, of.group(1) if of else "")


def uri_of(path: str | Path) -> str:
    uri = from_fs_path(str(path))
    assert uri is not None
    return uri


def path_of(uri: str) -> str:
    """The file path of ``uri`` (the URI itself when it is not a file)."""
    return to_fs_path(uri) or uri


class Files:
    """Open documents first, files on disk next. ``open_texts`` gives the open documents' live texts."""

    def __init__(self, open_texts: Callable[[], Mapping[str, str]]):
        self._open_texts = open_texts
        self._disk: dict[str, tuple[float, str, Header]] = {}  # path -> (mtime, text, header)

    def text(self, uri: str) -> str | None:
        """The document's live text, else the file's text on disk, else None."""
        live = self._open_texts().get(uri)
        if live is not None:
            return live
        entry = self._on_disk(path_of(uri))
        return entry[1] if entry else None

    def header(self, uri: str) -> Header:
        text = self.text(uri)
        return read_header(uri, text) if text is not None else Header("")

    def neighbours(self, uri: str) -> list[str]:
        """The open documents and the ``.pddl`` files of ``uri``'s folder, other than ``uri``: open ones
        first, each once."""
        found = [u for u in self._open_texts() if u != uri]
        folder = Path(path_of(uri)).parent
        try:
            names = sorted(os.listdir(folder))
        except OSError:
            names = []
        seen = set(found) | {uri}
        for name in names:
            if name.lower().endswith(".pddl"):
                other = uri_of(folder / name)
                if other not in seen:
                    seen.add(other)
                    found.append(other)
        return found

    def domain_for(self, uri: str) -> str | None:
        """The domain of a problem: the file its ``;; !domain: FILE`` comment chooses when it is there;
        else the one domain named by ``(:domain NAME)``, an open document first, then the files of its
        folder by name (:meth:`domain_candidates` lists them all: a diagnostic says when there are
        several); None when there is none (or ``uri`` is no problem)."""
        if self.header(uri).kind != PROBLEM:
            return None
        chosen = self.chosen_domain(uri)
        if chosen is not None and self.text(chosen) is not None:
            return chosen
        candidates = self.domain_candidates(uri)
        return candidates[0] if candidates else None

    def chosen_domain(self, uri: str) -> str | None:
        """The URI of the file a problem's ``;; !domain: FILE`` comment names (whether or not it exists)."""
        found = CHOSEN.search(self.text(uri) or "")
        if found is None:
            return None
        return uri_of(os.path.normpath(Path(path_of(uri)).parent / found.group(1)))

    def domain_candidates(self, uri: str) -> list[str]:
        """Every domain, open or in the problem's folder, that its ``(:domain NAME)`` names: open ones
        first (the most recently opened last), then the folder's files by name."""
        header = self.header(uri)
        if header.kind != PROBLEM or not header.domain:
            return []
        wanted = header.domain.lower()
        return [
            other
            for other in self.neighbours(uri)
            if (h := self.header(other)).kind == DOMAIN and h.name.lower() == wanted
        ]

    def domains_near(self, uri: str) -> list[str]:
        """Every domain among the open documents and ``uri``'s folder."""
        return [other for other in self.neighbours(uri) if self.header(other).kind == DOMAIN]

    def problems_of(self, domain_uri: str) -> list[str]:
        """The problems (open, and in the domain's folder) whose ``(:domain NAME)`` names it."""
        name = self.header(domain_uri).name.lower()
        return [
            other
            for other in self.neighbours(domain_uri)
            if (h := self.header(other)).kind == PROBLEM and h.domain.lower() == name and name
        ]

    def _on_disk(self, path: str) -> tuple[float, str, Header] | None:
        try:
            stat = os.stat(path)
            if stat.st_size > _LARGEST:
                return None
            cached = self._disk.get(path)
            if cached is not None and cached[0] == stat.st_mtime:
                return cached
            text = Path(path).read_bytes().decode("utf-8-sig")
        except (OSError, UnicodeDecodeError):
            return None
        entry = (stat.st_mtime, text, read_header(path, text))
        self._disk[path] = entry
        return entry
