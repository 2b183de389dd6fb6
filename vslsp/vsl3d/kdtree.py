"""A *k*-d tree over a point cloud with exact K-nearest-neighbour and radius search, batched
in numpy (paper, section "VSL-3D": "The points generated in voxelization phase are stored in a
Kd-tree structure. Then, K Nearest-Neighbor search (KNN) is applied").

The tree is balanced: every level splits each node at the median of its widest axis, down to
leaves of at most ``leaf_size`` points, so it is a complete binary tree in heap order (node
``i`` has children ``2i+1`` and ``2i+2``) and each node's points are one contiguous run of a
permutation. A batch of queries walks it level by level: a (query, node) pair survives while
the node's bounding box lies within the query's search bound, and the surviving leaves are
searched exhaustively. For KNN the bound is the K-th distance among the points of the
smallest node around the query that holds K points, so the search is exact.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vslsp.errors import InputError

_CHUNK = 4096  # queries per batch: bounds the (pairs, leaf points) arrays to a few MB


@dataclass(frozen=True, eq=False)
class Neighbours:
    """Neighbour pairs, flat and sorted by query then distance: query ``query[j]`` has point
    ``index[j]`` at ``distance[j]`` (all (P,))."""

    query: np.ndarray
    index: np.ndarray
    distance: np.ndarray

    def counts(self, n_queries: int) -> np.ndarray:
        """How many neighbours each of the ``n_queries`` queries has (n_queries,)."""
        return np.bincount(self.query, minlength=n_queries)


class KDTree:
    """A balanced *k*-d tree over ``points`` (N, 3)."""

    def __init__(self, points: np.ndarray, leaf_size: int = 16) -> None:
        points = np.asarray(points, dtype=float)
        if points.ndim != 2 or points.shape[1] != 3 or len(points) == 0:
            raise InputError(f"a k-d tree needs a non-empty (N, 3) cloud, got shape {points.shape}")
        if leaf_size < 1:
            raise InputError(f"leaf_size must be >= 1, got {leaf_size}")
        self.points = points
        n = len(points)
        # floor: every leaf keeps leaf_size to 2 * leaf_size points, none is empty
        self.depth = int(np.floor(np.log2(n / leaf_size))) if n >= 2 * leaf_size else 0
        order = np.arange(n)
        starts, sizes = np.array([0]), np.array([n])
        self._sizes = [sizes]  # node sizes per level
        for _ in range(self.depth):
            node = np.repeat(np.arange(len(sizes)), sizes)
            ordered = points[order]
            spread = (np.maximum.reduceat(ordered, starts, axis=0)
                      - np.minimum.reduceat(ordered, starts, axis=0))
            axis = np.argmax(spread, axis=1)
            values = ordered[np.arange(n), axis[node]]
            order = order[np.lexsort((values, node))]
            left = sizes // 2
            starts = np.column_stack([starts, starts + left]).ravel()
            sizes = np.column_stack([left, sizes - left]).ravel()
            self._sizes.append(sizes)
        self.order = order
        self.starts = starts
        ordered = points[order]
        # Leaf boxes, then every level's boxes from its children's (heap order).
        lower = np.minimum.reduceat(ordered, starts, axis=0)
        upper = np.maximum.reduceat(ordered, starts, axis=0)
        self._lower, self._upper = [lower], [upper]
        for _ in range(self.depth):
            lower = np.minimum(lower[0::2], lower[1::2])
            upper = np.maximum(upper[0::2], upper[1::2])
            self._lower.insert(0, lower)
            self._upper.insert(0, upper)
        # Leaf points padded to a common width with +inf (never within any bound).
        width = int(sizes.max())
        slot = np.arange(n) - np.repeat(starts, sizes)
        leaf = np.repeat(np.arange(len(sizes)), sizes)
        self._leaf_points = np.full((len(sizes), width, 3), np.inf)
        self._leaf_points[leaf, slot] = ordered
        self._leaf_index = np.full((len(sizes), width), -1)
        self._leaf_index[leaf, slot] = order

    def __len__(self) -> int:
        return len(self.points)

    def query(self, queries: np.ndarray, k: int = 1,
              max_distance: float | None = None) -> tuple[np.ndarray, np.ndarray]:
        """The ``k`` nearest points of each query (Q, 3): distances (Q, k) ascending and point
        indices (Q, k). A query that is a point of the tree finds itself first (distance 0).

        With ``max_distance`` only points that near count (a much smaller search, as ICP and
        change detection need): missing neighbours have distance inf and index -1."""
        queries = self._check(queries)
        if not 1 <= k <= len(self):
            raise InputError(f"k must be between 1 and the {len(self)} points of the tree, got {k}")
        distances = np.full((len(queries), k), np.inf)
        indices = np.full((len(queries), k), -1, dtype=np.int64)
        for begin in range(0, len(queries), _CHUNK):
            chunk = queries[begin:begin + _CHUNK]
            if max_distance is None:
                found = self._search(chunk, self._knn_bound(chunk, k), k)
                distances[begin:begin + len(chunk)] = found.distance.reshape(-1, k)
                indices[begin:begin + len(chunk)] = found.index.reshape(-1, k)
            else:
                # The k-th distance of a nearby node often bounds tighter than max_distance.
                bound2 = np.minimum(self._knn_bound(chunk, k), float(max_distance) ** 2)
                found = self._search(chunk, bound2, k)
                rank = np.arange(len(found.query)) - np.searchsorted(found.query, found.query)
                distances[begin + found.query, rank] = found.distance
                indices[begin + found.query, rank] = found.index
        return distances, indices

    def query_radius(self, queries: np.ndarray, radius: float,
                     max_neighbours: int | None = None) -> Neighbours:
        """All points within ``radius`` (m, inclusive) of each query (Q, 3), at most the
        ``max_neighbours`` nearest when given."""
        queries = self._check(queries)
        if not radius > 0.0:
            raise InputError(f"search radius must be > 0 m, got {radius}")
        parts = []
        for begin in range(0, len(queries), _CHUNK):
            chunk = queries[begin:begin + _CHUNK]
            found = self._search(chunk, np.full(len(chunk), radius * radius), max_neighbours)
            parts.append((found.query + begin, found.index, found.distance))
        return Neighbours(*(np.concatenate(column) for column in zip(*parts)))

    def _check(self, queries: np.ndarray) -> np.ndarray:
        queries = np.atleast_2d(np.asarray(queries, dtype=float))
        if queries.ndim != 2 or queries.shape[1] != 3:
            raise InputError(f"queries must be an (Q, 3) array, got shape {queries.shape}")
        return queries

    def _knn_bound(self, queries: np.ndarray, k: int) -> np.ndarray:
        """Squared distance (Q,) to the k-th point of the deepest node around each query that
        holds at least k points: an upper bound of the k-th nearest neighbour's."""
        level = max(lv for lv, sizes in enumerate(self._sizes) if sizes.min() >= k)
        node = np.zeros(len(queries), dtype=np.int64)
        for lv in range(level):
            # Descend towards the child whose box is nearer (either child gives a valid bound).
            near_left = (_box_distance2(queries, self._lower[lv + 1][2 * node], self._upper[lv + 1][2 * node])
                         <= _box_distance2(queries, self._lower[lv + 1][2 * node + 1],
                                           self._upper[lv + 1][2 * node + 1]))
            node = 2 * node + np.where(near_left, 0, 1)
        leaves_per_node = 2 ** (self.depth - level)
        first = node * leaves_per_node
        block = self._leaf_points[first[:, None] + np.arange(leaves_per_node)].reshape(len(queries), -1, 3)
        offset = block - queries[:, None, :]
        d2 = np.einsum("qsi,qsi->qs", offset, offset)
        return np.partition(d2, k - 1, axis=1)[:, k - 1]

    def _search(self, queries: np.ndarray, bound2: np.ndarray, keep: int | None) -> Neighbours:
        """Points within squared distance ``bound2`` (Q,) of each query, the ``keep`` nearest."""
        query = np.arange(len(queries))
        node = np.zeros(len(queries), dtype=np.int64)
        slack = bound2 * (1.0 + 1e-9) + 1e-18  # box and point distances round differently
        for lv in range(self.depth + 1):
            near = _box_distance2(queries[query], self._lower[lv][node], self._upper[lv][node]) <= slack[query]
            query, node = query[near], node[near]
            if lv < self.depth:
                query = np.repeat(query, 2)
                node = (2 * np.repeat(node, 2) + np.tile([1, 2], len(node))) - 1
        offset = self._leaf_points[node] - queries[query][:, None, :]
        d2 = np.einsum("psi,psi->ps", offset, offset)
        if keep == 1:  # nearest only: the best slot of each pair, then the best pair of each query
            slot = np.argmin(d2, axis=1)
            best = d2[np.arange(len(node)), slot]
            scaled = np.minimum(best / (float(bound2.max()) * (1.0 + 1e-9) + 1e-300), 1.0 - 1e-9)
            ranked = np.argsort(query + scaled, kind="stable")
            first = ranked[np.r_[True, query[ranked][1:] != query[ranked][:-1]]] if len(ranked) else ranked
            return Neighbours(query[first], self._leaf_index[node[first], slot[first]], np.sqrt(best[first]))
        within = d2 <= slack[query][:, None]
        pair, slot = np.nonzero(within)
        query, index, d2 = query[pair], self._leaf_index[node[pair], slot], d2[pair, slot]
        # Sort by query, then distance: one argsort of query + d2 scaled into [0, 1).
        scale = max(float(bound2.max()), 1e-300) * (1.0 + 1e-9)
        ranked = np.argsort(query + d2 / scale, kind="stable")
        query, index, d2 = query[ranked], index[ranked], d2[ranked]
        if keep is not None:
            first = np.searchsorted(query, query, side="left")
            rank = np.arange(len(query)) - first
            chosen = rank < keep
            query, index, d2 = query[chosen], index[chosen], d2[chosen]
        return Neighbours(query, index, np.sqrt(d2))


def _box_distance2(points: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> np.ndarray:
    """Squared distance (N,) from points (N, 3) to axis-aligned boxes (N, 3)-(N, 3)."""
    gap = np.maximum(np.maximum(lower - points, points - upper), 0.0)
    return np.einsum("ij,ij->i", gap, gap)


def brute_force_knn(points: np.ndarray, queries: np.ndarray, k: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """Exact KNN by comparing every query with every point (the reference for the tree):
    distances (Q, k) ascending and indices (Q, k)."""
    points = np.asarray(points, dtype=float)
    queries = np.atleast_2d(np.asarray(queries, dtype=float))
    distances = np.empty((len(queries), k))
    indices = np.empty((len(queries), k), dtype=np.int64)
    step = max(1, 2_000_000 // max(len(points), 1))
    squared = np.einsum("ij,ij->i", points, points)
    for begin in range(0, len(queries), step):
        chunk = queries[begin:begin + step]
        d2 = np.einsum("ij,ij->i", chunk, chunk)[:, None] + squared[None, :] - 2.0 * chunk @ points.T
        nearest = np.argpartition(d2, k - 1, axis=1)[:, :k] if k < len(points) else np.tile(
            np.arange(len(points)), (len(chunk), 1))
        exact = np.sum((points[nearest] - chunk[:, None, :]) ** 2, axis=2)
        ranked = np.argsort(exact, axis=1, kind="stable")
        indices[begin:begin + len(chunk)] = np.take_along_axis(nearest, ranked, axis=1)
        distances[begin:begin + len(chunk)] = np.sqrt(np.take_along_axis(exact, ranked, axis=1))
    return distances, indices
