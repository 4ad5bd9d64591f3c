"""Submissions from other codes: metadata + results, validated and checked.

A submission is one folder (``submissions/<problem>/<code>-<label>/`` in the repository):
``submission.toml``, the metadata validated by the JSON Schema
``submission.schema.json`` beside this module (code, version and commit, URL, who ran it
and when, method, element, mesh, tolerances, hardware, the exact command), and the results
file it names, which ``debench check PROBLEM RESULTS`` reads. Its sha256 is part of the
metadata, so results and metadata cannot drift apart unnoticed.

:func:`load` refuses a folder whose metadata is incomplete or invalid
(:class:`SubmissionError`, naming every missing or invalid field) or whose results file
does not match its checksum; :func:`check` then compares the results with the problem's
reference exactly as ``debench check`` does, at the submitter's stated tolerance (the
optional ``[check]`` table: ``rtol``/``atol`` with their ``reason``, the reference's stated
accuracy being the floor) and also at the reference's stated accuracy alone.
"""

from __future__ import annotations

import datetime as _dt
import hashlib
import json
import tomllib
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from typing import Any

import jsonschema
from debench.reference import problems
from debench.reference.comparison import compare
from debench.reference.results_files import METADATA_NAME, UsageError, read_results

SCHEMA_NAME = "submission.schema.json"


class SubmissionError(ValueError):
    """A submission that cannot be judged: incomplete or invalid metadata, a results file
    that is missing or does not match its checksum, a problem or quantity that does not
    exist."""


@cache
def schema() -> dict:
    """The JSON Schema of ``submission.toml`` (as parsed by :mod:`tomllib`)."""
    return json.loads((Path(__file__).with_name(SCHEMA_NAME)).read_text(encoding="utf-8"))


def _jsonable(obj: Any) -> Any:
    """TOML dates and times as their ISO 8601 text (what the schema validates)."""
    if isinstance(obj, dict):
        return {k: _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, list):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, _dt.date | _dt.time):
        return obj.isoformat()
    return obj


def metadata_errors(meta: dict) -> list[str]:
    """Every schema violation of ``meta``, one line each, naming the field
    (``code.version: missing (required)``, ``results_sha256: 'xyz' does not match ...``)."""
    validator = jsonschema.Draft202012Validator(schema())
    out = []
    for err in sorted(validator.iter_errors(_jsonable(meta)),
                      key=lambda e: [str(p) for p in e.absolute_path]):
        where = ".".join(str(p) for p in err.absolute_path)
        if err.validator == "required":
            missing = [f for f in err.validator_value if f not in err.instance]
            out += [f"{where + '.' if where else ''}{f}: missing (required)" for f in missing]
        elif err.validator == "additionalProperties":
            known = set(err.schema.get("properties", {}))
            extra = sorted(set(err.instance) - known)
            out += [f"{where + '.' if where else ''}{f}: not a field of the format "
                    f"(known: {', '.join(sorted(known))})" for f in extra]
        elif err.validator == "dependentRequired":
            out.append(f"{where}: {err.message}")
        else:
            out.append(f"{where or '(top level)'}: {err.message}")
    return out


def sha256_of(path: Path) -> str:
    h = hashlib.sha256()
    with Path(path).open("rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


@dataclass(frozen=True)
class Submission:
    """A loaded submission whose metadata passed the schema and whose results file
    matches its checksum."""

    folder: Path
    meta: dict

    @property
    def problem(self) -> str:
        return self.meta["problem"]

    @property
    def quantity(self) -> str:
        return self.meta["quantity"]

    @property
    def results(self) -> Path:
        return self.folder / self.meta["results"]

    @property
    def code(self) -> str:
        return self.meta["code"]["name"]

    @property
    def label(self) -> str:
        """``<code> <version>`` and the folder name (which says what variant ran)."""
        return f"{self.meta['code']['name']} {self.meta['code']['version']} ({self.folder.name})"

    @property
    def claims(self) -> dict:
        return self.meta.get("check", {})


def load(folder) -> Submission:
    """Read and validate a submission folder; :class:`SubmissionError` naming every
    missing or invalid field, or the checksum mismatch, or an unknown problem/quantity."""
    folder = Path(folder)
    path = folder / METADATA_NAME
    if not path.is_file():
        raise SubmissionError(f"{folder}: no {METADATA_NAME} (a submission is a folder with "
                              "the metadata file and the results file it names)")
    try:
        meta = tomllib.loads(path.read_text(encoding="utf-8"))
    except tomllib.TOMLDecodeError as exc:
        raise SubmissionError(f"{path}: not valid TOML ({exc})") from None
    errors = metadata_errors(meta)
    if errors:
        raise SubmissionError(f"{path}: refused, the metadata is incomplete or invalid "
                              f"({len(errors)} field(s)):\n  " + "\n  ".join(errors))
    try:
        prob = problems.get(meta["problem"])
        prob.quantity(meta["quantity"])
    except problems.ProblemError as exc:
        raise SubmissionError(f"{path}: {exc}") from None
    results = folder / meta["results"]
    if not results.is_file():
        raise SubmissionError(f"{path}: the results file {meta['results']} is not in "
                              f"{folder}")
    digest = sha256_of(results)
    if digest != meta["results_sha256"]:
        raise SubmissionError(f"{path}: results_sha256 {meta['results_sha256']} does not "
                              f"match {meta['results']} (sha256 {digest}): the results "
                              "changed after the metadata was written")
    return Submission(folder=folder, meta=meta)


@dataclass(frozen=True)
class Outcome:
    """A submission checked against its problem.

    ``stated``: the comparison at the reference's stated accuracy alone (``debench check``
    without ``--rtol``); ``declared``: at the submitter's stated tolerance (``[check]``
    rtol/atol; None when the submission states none). ``passed`` is the verdict that sets
    the exit code: ``declared`` when stated, else ``stated``.
    """

    submission: Submission
    stated: Any
    declared: Any

    @property
    def verdict(self):
        return self.declared if self.declared is not None else self.stated

    @property
    def passed(self) -> bool:
        return self.verdict.passed

    @property
    def claim_holds(self) -> bool | None:
        """Whether the outcome is the claimed one (None: no claim in the metadata)."""
        claimed = self.submission.claims.get("claimed")
        if claimed is None:
            return None
        return (claimed == "match") == self.passed


def check(sub: Submission) -> Outcome:
    """Compare the results of ``sub`` with its problem's reference (like ``debench check``:
    units by meaning, full coverage unless ``[check] partial = true``)."""
    prob = problems.get(sub.problem)
    try:
        (qname,), cols = read_results(sub.results, sub.quantity, prob)
    except UsageError as exc:
        raise SubmissionError(f"{sub.results}: {exc}") from None
    q = prob.quantity(qname)
    coords = {c: cols[c] for c in q.coordinates if c in cols}
    cov = "partial" if sub.claims.get("partial", False) else "full"
    try:
        stated = compare(prob.id, q.name, cols[qname], coords, coverage=cov)
        declared = None
        if "rtol" in sub.claims or "atol" in sub.claims:
            declared = compare(prob.id, q.name, cols[qname], coords,
                               rtol=sub.claims.get("rtol"), atol=sub.claims.get("atol"),
                               coverage=cov)
    except ValueError as exc:  # CoverageError and bad coordinates included
        raise SubmissionError(f"{sub.results}: {exc}") from None
    return Outcome(submission=sub, stated=stated, declared=declared)


def discover(root) -> list[Path]:
    """Every submission folder under ``root`` (folders holding a ``submission.toml``),
    sorted."""
    return sorted(p.parent for p in Path(root).rglob(METADATA_NAME))


def curated_root() -> Path:
    """``submissions/`` of the source checkout (curated submissions are not package
    data: they belong to the repository, as the adapters do)."""
    return Path(__file__).resolve().parent.parent / "submissions"
