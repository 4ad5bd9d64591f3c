"""Discovery metadata (ACDD-1.3) of every dataset, and the standards check by the real tool.

The one writer (:func:`debench.reference.datasets.write_dataset`) takes the global
attributes of :func:`acdd_attributes` and the per-variable ``coverage_content_type`` of
:func:`coverage_content_type`; the data card (:mod:`debench.reference.datacard`) lists
:data:`NOT_APPLICABLE` and :data:`PLACEHOLDERS` so that a reader knows which ACDD
attributes are absent on purpose and which carry a stand-in value. :func:`check_file` runs
the IOOS ``compliance-checker`` (CF-1.10 and ACDD-1.3) on one file and returns what fails.

Nothing here invents a person, an address or a URL: the repository has no public address
yet (``debench.reference.provenance.repository_url()`` is ``None``: ``[project.urls]``
of ``pyproject.toml`` names none); when it gets one the writer adds ``creator_url``,
``publisher_url`` and ``metadata_link`` from it.
"""

from __future__ import annotations

import re
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from debench.reference import __version__
from debench.reference.provenance import repository_url

#: The group that writes the datasets (no individual authors are stated).
GROUP = "debench developers"
PROJECT = ("debench: verification and reproducibility benchmark for the mechanics of "
           "dielectric elastomer actuators (Zeng 2020)")
PROCESSING_LEVEL = ("model results: reference solutions computed by debench from the equations "
                    "of Zeng (2020), cross-checked by independent implementations; no "
                    "measured data")
ACKNOWLEDGEMENT = ("Equations, parameters and printed values reproduced from the PhD "
                   "dissertation of C. Zeng (2020, The University of Akron); see references.")
COMMENT = ("Verify the file against the sha256 in MANIFEST.json of its directory; the data "
           "card (README.md) lists every variable, and `debench problems` the stated accuracy.")
#: No quantity here (stretches, normalised voltages, moduli of a film) has an entry in the
#: CF standard name table; the text avoids the phrase the CF checker parses for a table
#: version (a version other than the packaged one makes it download a table).
STANDARD_NAME_VOCABULARY = ("CF standard names: none used (the table has no entry for these "
                            "quantities)")

#: ACDD-1.3 attributes (global, or ``standard_name`` per variable) that do not apply.
NOT_APPLICABLE = {
    "geospatial_*": "the data are not located on the Earth (material points, a film, a plate)",
    "time_coverage_*": "the data are not a time series of observations",
    "platform*, instrument*": "computed, not observed",
    "keywords_vocabulary": "the keywords are free text (no controlled vocabulary)",
    "program": "no funding programme",
    "standard_name": "no CF standard name exists for these quantities (stretches, normalised "
                     "voltages, electroelastic moduli); `long_name` and `units` describe each",
    "creator_email, publisher_email": "no contact address is published",
    "creator_url, publisher_url, metadata_link": "the repository has no public address yet; "
                                                 "the writer adds them once it has one",
    "contributor_name, contributor_role": "the contributors are not named",
    "creator_institution, publisher_institution": "no institution is stated "
                                                  "(see the placeholder `institution`)",
    "date_issued": "no dataset has been formally released",
}
#: ACDD-1.3 attributes that carry a stand-in value until the project states the real one.
PLACEHOLDERS = {
    "creator_name, publisher_name, institution": f'"{GROUP}": the authors and their '
                                                 "institution are not stated",
    "naming_authority": '"debench": the project has no reverse-DNS domain; `id` is the '
                        "file stem, unique within the project",
}

#: ``coverage_content_type`` (ACDD-1.3 vocabulary) of a data variable, by name pattern.
#: Everything else is ``modelResult``; coordinates are ``coordinate``.
_COVERAGE_BY_NAME = (
    (re.compile(r"(^|_)(error|tolerance|residual|rtol|atol)(_|$)"), "qualityInformation"),
    (re.compile(r"(^|_)(printed|thesis)(_|$)"), "referenceInformation"),
    (re.compile(r"^(ndof|n_?elements|level|nelements|n_dof|iterations?)(_|$)"),
     "auxiliaryInformation"),
)
COVERAGE_CONTENT_TYPES = ("image", "thematicClassification", "physicalMeasurement",
                          "auxiliaryInformation", "qualityInformation",
                          "referenceInformation", "modelResult", "coordinate")


def coverage_content_type(name: str, *, is_coordinate: bool) -> str:
    """The ACDD ``coverage_content_type`` of variable ``name`` (a builder may set its own)."""
    if is_coordinate:
        return "coordinate"
    for pattern, kind in _COVERAGE_BY_NAME:
        if pattern.search(name):
            return kind
    return "modelResult"


def acdd_attributes(name: str, now: str) -> dict[str, str]:
    """Global ACDD-1.3 attributes of dataset ``name`` written at ``now`` (ISO 8601)."""
    attrs = {
        "id": name, "naming_authority": "debench", "institution": GROUP,
        "creator_type": "group", "publisher_name": GROUP, "publisher_type": "group",
        "project": PROJECT, "processing_level": PROCESSING_LEVEL,
        "acknowledgement": ACKNOWLEDGEMENT, "comment": COMMENT,
        "standard_name_vocabulary": STANDARD_NAME_VOCABULARY,
        "product_version": __version__, "date_modified": now,
        "date_metadata_modified": now,
    }
    url = repository_url()
    if url:
        attrs.update(creator_url=url, publisher_url=url, metadata_link=url)
    return attrs


def _not_applicable(attr: str) -> bool:
    for key in NOT_APPLICABLE:
        for item in key.split(", "):
            if item == attr or (item.endswith("*") and attr.startswith(item[:-1])):
                return True
    return False


@dataclass
class Findings:
    """What the compliance checker reports for one file.

    Attributes
    ----------
    cf_failures
        ``(check name, messages)`` of every CF-1.10 check that lost points.
    acdd_missing
        ACDD attributes reported missing that are not in :data:`NOT_APPLICABLE`
        (``"<variable>:<attribute>"`` for per-variable ones).
    acdd_suggested_missing
        The same for the ACDD *suggested* attributes (reported, not required).
    acdd_failures
        Other ACDD checks that lost points (e.g. a malformed date).
    checker_errors
        ``{check name: exception text}`` of checks that crashed inside the checker.
    scores
        ``{checker: (scored, possible)}``.
    """

    cf_failures: list[tuple[str, list[str]]] = field(default_factory=list)
    acdd_missing: set[str] = field(default_factory=set)
    acdd_suggested_missing: set[str] = field(default_factory=set)
    acdd_failures: list[tuple[str, list[str]]] = field(default_factory=list)
    checker_errors: dict[str, str] = field(default_factory=dict)
    scores: dict[str, tuple[int, int]] = field(default_factory=dict)


#: Priority of the ACDD *recommended* attributes in the checker (3 = highly recommended,
#: 1 = suggested).
RECOMMENDED = 2
_MISSING_VAR = re.compile(r'^variable "(.+)" missing the following attributes:$')
_NOT_PRESENT = re.compile(r"^(?:Attr )?(\S+?)(?:/\S+)? (?:is )?not present$")
_EXTENTS = re.compile(r"^geospatial_(lat|lon)_extents_match$")


def check_file(path: Path, checks: tuple[str, ...] = ("cf:1.10", "acdd:1.3")) -> Findings:
    """Run the IOOS compliance-checker on ``path`` and sort its findings.

    Raises ``ImportError`` when ``compliance-checker`` is not installed (it is in the
    ``test`` extra).
    """
    found = Findings()
    with warnings.catch_warnings():  # the checker's own deprecation notices
        warnings.simplefilter("ignore")
        from compliance_checker.runner import CheckSuite

        suite = CheckSuite()
        suite.load_all_available_checkers()
        ds = suite.load_dataset(str(path))
        try:
            results = suite.run_all(ds, list(checks), skip_checks=[])
        finally:
            ds.close()
    for checker, (groups, errors) in results.items():
        s = suite.build_structure(checker, groups, str(path))
        found.scores[checker] = (s["scored_points"], s["possible_points"])
        found.checker_errors.update({f"{checker}:{k}": repr(v[0]) for k, v in errors.items()})
        for r in groups:
            scored, possible = r.value if isinstance(r.value, tuple) else (int(r.value), 1)
            if not possible or scored >= possible:
                continue
            msgs = [str(m) for m in r.msgs]
            if checker.startswith("cf"):
                found.cf_failures.append((r.name, msgs))
            elif (m := _MISSING_VAR.match(r.name)):
                found.acdd_missing |= {f"{m[1]}:{a}" for a in msgs if not _not_applicable(a)}
            elif _EXTENTS.match(r.name):
                continue  # geospatial extents: not applicable (NOT_APPLICABLE)
            else:
                missing = [_NOT_PRESENT.match(m) for m in msgs]
                if all(missing):
                    names = {m[1] for m in missing if not _not_applicable(m[1])}
                    if r.weight >= RECOMMENDED:
                        found.acdd_missing |= names
                    else:
                        found.acdd_suggested_missing |= names
                else:
                    found.acdd_failures.append((r.name, msgs))
    return found


def summary(findings: Findings) -> dict[str, Any]:
    """A JSON-friendly summary (for messages)."""
    return {"scores": findings.scores, "cf_failures": findings.cf_failures,
            "acdd_missing": sorted(findings.acdd_missing),
            "acdd_suggested_missing": sorted(findings.acdd_suggested_missing),
            "acdd_failures": findings.acdd_failures, "checker_errors": findings.checker_errors}
