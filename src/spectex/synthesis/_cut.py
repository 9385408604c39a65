"""Quilting's block placement and its minimum-error boundary cuts (numba kernels; the cut's path is
``spectex._seams.min_cut_path``, which the fit's fill of one-off content shares)."""

from __future__ import annotations

import numba
import numpy as np

from .._seams import min_cut_path


@numba.njit(cache=True, nogil=True)
def _side_width(line):
    """How many leading entries of a boolean line are True (1 .. n - 1)."""
    n = line.shape[0]
    w = n
    for k in range(n):
        if not line[k]:
            w = k
            break
    return max(1, min(w, n - 1))


@numba.njit(cache=True, nogil=True, inline="always")
def _best_error(err, boxes):
    """The least error outside ``boxes`` (or anywhere, if every candidate is in one)."""
    ph, pw = err.shape
    best = np.inf
    for y in range(ph):
        for x in range(pw):
            skip = False
            for k in range(boxes.shape[0]):
                if boxes[k, 0] <= y < boxes[k, 1] and boxes[k, 2] <= x < boxes[k, 3]:
                    skip = True
                    break
            if not skip and err[y, x] < best:
                best = err[y, x]
    if best == np.inf:  # every candidate is a continuation
        for y in range(ph):
            for x in range(pw):
                if err[y, x] < best:
                    best = err[y, x]
    return best


@numba.njit(cache=True, nogil=True, inline="always")
def _pick(err, limit, u):
    """The position of the ``int(u * count)``-th candidate (raster order) with error <= ``limit``."""
    ph, pw = err.shape
    count = 0
    for y in range(ph):
        for x in range(pw):
            if err[y, x] <= limit:
                count += 1
    target = min(int(u * count), count - 1)
    sy = sx = 0
    seen = 0
    for y in range(ph):
        for x in range(pw):
            if err[y, x] <= limit:
                if seen == target:
                    sy, sx = y, x
                seen += 1
    return sy, sx


@numba.njit(cache=True, nogil=True, inline="always")
def _squared_difference(view, ex, sy, sx):
    """Per pixel, the squared colour difference of ``view`` and the block of ``ex`` at ``(sy, sx)``."""
    b = view.shape[0]
    nch = view.shape[2]
    diff = np.empty((b, b), dtype=np.float64)
    for i in range(b):
        for j in range(b):
            s = 0.0
            for c in range(nch):
                d = view[i, j, c] - ex[sy + i, sx + j, c]
                s += d * d
            diff[i, j] = s
    return diff


@numba.njit(cache=True, nogil=True, inline="always")
def _new_side(diff, known):
    """True where the block is pasted: on the new side of the cut of every filled side."""
    b = diff.shape[0]
    new = np.ones((b, b), dtype=np.bool_)
    mid = b // 2
    if known[:, 0].all():  # left
        w = _side_width(known[mid, :])
        path = min_cut_path(diff[:, :w].copy())
        for i in range(b):
            for j in range(path[i]):
                new[i, j] = False
    if known[0, :].all():  # top
        h = _side_width(np.ascontiguousarray(known[:, mid]))
        path = min_cut_path(diff[:h, :].T.copy())
        for j in range(b):
            for i in range(path[j]):
                new[i, j] = False
    if known[:, b - 1].all():  # right (tileable quilts)
        w = _side_width(np.ascontiguousarray(known[mid, ::-1]))
        path = min_cut_path(diff[:, b - w:].copy())
        for i in range(b):
            for j in range(b - w + path[i] + 1, b):
                new[i, j] = False
    if known[b - 1, :].all():  # bottom (tileable quilts)
        h = _side_width(np.ascontiguousarray(known[::-1, mid]))
        path = min_cut_path(diff[b - h:, :].T.copy())
        for j in range(b):
            for i in range(b - h + path[j] + 1, b):
                new[i, j] = False
    return new


def place_block(err, boxes, tolerance, u, view, known, ex):
    """Choose a block among the near-best and paste it along its boundary cuts.

    Parameters
    ----------
    err : float32 array (ph, pw)
        Overlap error of every candidate position.
    boxes : int64 array (m, 4)
        ``y0, y1, x0, x1`` of candidate boxes left out of the best error
        (verbatim continuations of neighbours); they stay candidates.
    tolerance : float
        Candidates within ``(1 + tolerance)`` of that best are eligible.
    u : float
        Uniform draw in [0, 1) picking one eligible candidate (raster order).
    view : float32 array (b, b, C)
        The output under the block (written in place).
    known : bool array (b, b)
        Which pixels of ``view`` were already filled.
    ex : float32 array (h, w, C)
        The exemplar.

    Returns
    -------
    (int, int)
        The chosen source position. Each side of the block whose edge is
        filled gets a minimum-error cut through the filled band next to it
        (its width measured along the middle of the edge); pixels on the new
        side of every cut, and all pixels not filled before, are pasted.
    """
    # The kernel always sees C-contiguous arrays: a slice of the canvas and a wrapped (copied)
    # block, or a sliced and a whole error map, would otherwise be two array layouts, two
    # compilations of the kernel (on a clean clone, each is seconds of the first run).
    block = np.ascontiguousarray(view)
    sy, sx = _place_block(np.ascontiguousarray(err), boxes, tolerance, u, block, known, ex)
    if block is not view:
        view[...] = block
    return sy, sx


@numba.njit(cache=True, nogil=True)
def _place_block(err, boxes, tolerance, u, view, known, ex):
    """:func:`place_block`'s kernel; ``view`` C-contiguous."""
    sy, sx = _pick(err, _best_error(err, boxes) * (1.0 + tolerance), u)
    new = _new_side(_squared_difference(view, ex, sy, sx), known)
    b = view.shape[0]
    for i in range(b):
        for j in range(b):
            if new[i, j] or not known[i, j]:
                for c in range(view.shape[2]):
                    view[i, j, c] = ex[sy + i, sx + j, c]
    return sy, sx
