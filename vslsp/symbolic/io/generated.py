"""Logistics problems of any size: the large PDDL inputs of the size tests and benchmarks.

The domain is IPC-1998 logistics (typed, STRIPS: trucks drive within a city, airplanes fly between
airports, both load and unload packages), which declares ``at`` as IPC domains do. A problem of
``n_objects`` objects splits them as an IPC instance does (most are packages) and puts every object
somewhere in the initial state, so its text grows linearly with ``n_objects``: about 28 bytes an
object (50 000 objects are 1.4 MB). Deterministic: the same ``n_objects`` gives the same text.
"""

from __future__ import annotations

from collections.abc import Iterator

LOGISTICS_DOMAIN = """\
; IPC-1998 logistics, typed (STRIPS): packages carried by trucks within a city and by airplanes
; between the cities' airports.
(define (domain logistics)
  (:requirements :strips :typing)
  (:types truck airplane - vehicle
          package vehicle - physobj
          airport location - place
          city place physobj - object)
  (:predicates (in-city ?loc - place ?city - city)
               (at ?obj - physobj ?loc - place)
               (in ?pkg - package ?veh - vehicle))
  (:action load-truck
    :parameters (?pkg - package ?truck - truck ?loc - place)
    :precondition (and (at ?truck ?loc) (at ?pkg ?loc))
    :effect (and (not (at ?pkg ?loc)) (in ?pkg ?truck)))
  (:action load-airplane
    :parameters (?pkg - package ?airplane - airplane ?loc - place)
    :precondition (and (at ?pkg ?loc) (at ?airplane ?loc))
    :effect (and (not (at ?pkg ?loc)) (in ?pkg ?airplane)))
  (:action unload-truck
    :parameters (?pkg - package ?truck - truck ?loc - place)
    :precondition (and (at ?truck ?loc) (in ?pkg ?truck))
    :effect (and (not (in ?pkg ?truck)) (at ?pkg ?loc)))
  (:action unload-airplane
    :parameters (?pkg - package ?airplane - airplane ?loc - place)
    :precondition (and (in ?pkg ?airplane) (at ?airplane ?loc))
    :effect (and (not (in ?pkg ?airplane)) (at ?pkg ?loc)))
  (:action drive-truck
    :parameters (?truck - truck ?loc-from - place ?loc-to - place ?city - city)
    :precondition (and (at ?truck ?loc-from) (in-city ?loc-from ?city) (in-city ?loc-to ?city))
    :effect (and (not (at ?truck ?loc-from)) (at ?truck ?loc-to)))
  (:action fly-airplane
    :parameters (?airplane - airplane ?loc-from - airport ?loc-to - airport)
    :precondition (at ?airplane ?loc-from)
    :effect (and (not (at ?airplane ?loc-from)) (at ?airplane ?loc-to))))
"""

#: Of every 20 objects: 1 city, 1 airport, 2 locations, 2 trucks, 14 packages (the last object is an airplane).
_SHARES = (("city", 1), ("airport", 1), ("location", 2), ("truck", 2), ("package", 14))
#: The first letters of each type's object names (c3 is a city, ap3 its airport).
_PREFIXES = {"city": "c", "airport": "ap", "location": "l", "truck": "t", "package": "p", "airplane": "pl"}
#: One package in this many is to be carried elsewhere (the goal); the others stay where they are.
_GOAL_EVERY = 10
#: Names per line of the ``:objects`` section.
_PER_LINE = 16


def logistics_problem(n_objects: int, name: str = "") -> str:
    """The text of a logistics problem of ``n_objects`` objects (at least 7: a city of each type of place
    and vehicle, and a package) for :data:`LOGISTICS_DOMAIN`."""
    if n_objects < 7:
        raise ValueError(f"a logistics problem needs at least 7 objects, got {n_objects}")
    counts = _counts(n_objects)
    names = {kind: [f"{_PREFIXES[kind]}{i}" for i in range(count)] for kind, count in counts.items()}
    return "".join(_problem(name or f"logistics-{n_objects}", names))


def _counts(n_objects: int) -> dict[str, int]:
    """How many objects of each type ``n_objects`` holds: the shares of :data:`_SHARES`, at least one
    of each, and one airplane."""
    rest = n_objects - 1  # the airplane
    counts = {kind: max(1, rest * share // 20) for kind, share in _SHARES}
    counts["package"] += rest - sum(counts.values())
    counts["airplane"] = 1
    return counts


def _problem(name: str, names: dict[str, list[str]]) -> Iterator[str]:
    cities, airports, locations = names["city"], names["airport"], names["location"]
    places = airports + locations
    yield f"(define (problem {name})\n  (:domain logistics)\n  (:objects\n"
    for kind, listed in names.items():
        for start in range(0, len(listed), _PER_LINE):
            chunk = listed[start : start + _PER_LINE]
            yield f"    {' '.join(chunk)}{f' - {kind}' if start + _PER_LINE >= len(listed) else ''}\n"
    yield "  )\n  (:init\n"
    for i, place in enumerate(places):  # every city has its airport first, then locations in turn
        yield f"    (in-city {place} {cities[i % len(cities)]})\n"
    for i, truck in enumerate(names["truck"]):
        yield f"    (at {truck} {places[i % len(places)]})\n"
    yield f"    (at {names['airplane'][0]} {airports[0]})\n"
    for i, package in enumerate(names["package"]):
        yield f"    (at {package} {places[(i * 7) % len(places)]})\n"
    yield "  )\n  (:goal (and\n"
    for i in range(0, len(names["package"]), _GOAL_EVERY):
        yield f"    (at {names['package'][i]} {places[(i * 7 + 1) % len(places)]})\n"
    yield "  ))\n)\n"
