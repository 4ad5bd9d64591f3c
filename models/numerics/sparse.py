"""Restrictions of sparse matrices of one fixed sparsity pattern (:class:`PatternRestriction`).

A finite-element form is assembled on one matrix graph at every state: the blocks a solver
needs (free DOFs, displacement and potential blocks) are the same selections of rows and
columns every time, and only the values change. The selections are made once, on a template
of the pattern whose values are the positions of the entries; later matrices are their
values gathered through that map.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import scipy.sparse as sp


class PatternRestriction:
    """``slicer(A)`` for every sparse matrix ``A`` of one sparsity pattern, by a gather of
    its values: ``restrict(A)`` for a compressed (CSR or CSC) matrix, ``restrict.coo(rows,
    cols, vals, shape)`` for assembled triplets (an NGSolve matrix's ``COO()``, converted as
    ``scipy.sparse.csr_matrix((vals, (rows, cols)), shape)``).

    ``slicer`` may only select rows and columns and convert formats (no arithmetic on the
    values). Applied once to the template of the pattern whose values are the positions
    1 .. nnz, it gives for every stored entry of its result the position of the value it
    holds; the restriction of a later matrix is its values gathered through that map into
    the result's structure, identical entry for entry to ``slicer(A)`` (explicit zeros and
    every bit of every value included) without SciPy's conversions and fancy indexing. The
    pattern of every matrix (format, shape, index arrays) is compared with the template's;
    another pattern rebuilds the map. A pattern with duplicate entries (which a conversion
    sums) is sliced directly. A slicer found to combine values raises ValueError."""

    def __init__(self, slicer: Callable[[sp.spmatrix], sp.spmatrix]):
        if not callable(slicer):
            raise TypeError(f"slicer must be callable, got {type(slicer).__name__}")
        self.slicer = slicer
        self._key: tuple | None = None
        self._out: tuple | None = None

    def __call__(self, A: sp.spmatrix) -> sp.spmatrix:
        if not (sp.issparse(A) and A.format in ("csr", "csc")):
            raise TypeError(f"A must be a CSR or CSC matrix, got {type(A).__name__}")
        key = (type(A), A.shape, A.indptr, A.indices)
        if not self._same(key):
            nnz = int(A.indptr[-1])
            template = type(A)((np.arange(1, nnz + 1, dtype=float), A.indices.copy(),
                                A.indptr.copy()), shape=A.shape)
            self._build(key, template if template.has_canonical_format else None, nnz)
        if self._out is None:
            return self.slicer(A)
        return self._gather(A.data)

    def coo(self, rows, cols, vals, shape: tuple[int, int]) -> sp.spmatrix:
        """``slicer`` of the matrix of the triplets ``(rows, cols, vals)`` of ``shape``."""
        rows, cols, vals = np.asarray(rows), np.asarray(cols), np.asarray(vals)
        if not rows.shape == cols.shape == vals.shape or rows.ndim != 1:
            raise ValueError(f"rows, cols and vals must be 1-D of one length, got "
                             f"{rows.shape}, {cols.shape}, {vals.shape}")
        shape = (int(shape[0]), int(shape[1]))
        key = ("coo", shape, rows, cols)
        if not self._same(key):
            nnz = rows.size
            template = sp.csr_matrix((np.arange(1, nnz + 1, dtype=float), (rows, cols)),
                                     shape=shape)
            self._build(key, template if template.nnz == nnz else None, nnz)
        if self._out is None:
            return self.slicer(sp.csr_matrix((vals, (rows, cols)), shape=shape))
        return self._gather(vals)

    def _same(self, key: tuple) -> bool:
        k = self._key
        return (k is not None and len(k) == len(key) and k[0] is key[0] and k[1] == key[1]
                and all(a.shape == b.shape and np.array_equal(a, b)
                        for a, b in zip(k[2:], key[2:], strict=True)))

    def _build(self, key: tuple, template, nnz: int) -> None:
        self._key = (*key[:2], *(np.array(a, copy=True) for a in key[2:]))
        self._out = None
        if template is None:
            return
        out = self.slicer(template)
        idx = out.data.astype(np.int64) - 1
        if not (np.array_equal(out.data, idx + 1.0) and np.all((idx >= 0) & (idx < nnz))
                and np.unique(idx).size == idx.size):
            raise ValueError("PatternRestriction: the slicer combines values (it may only "
                             "select rows and columns and convert formats)")
        self._out = (type(out), out.shape, out.indices, out.indptr, idx)

    def _gather(self, values: np.ndarray) -> sp.spmatrix:
        cls, shape, indices, indptr, idx = self._out
        return cls((values[idx], indices, indptr), shape=shape)
