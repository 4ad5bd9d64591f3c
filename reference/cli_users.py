"""The users' subcommands of ``debench`` (:mod:`debench.reference.cli`): ``problems``
(list the reference problems or print one) and ``check`` (a results file or a submission
folder against a problem's reference); ``cite`` is :mod:`debench.reference.cli_cite`."""

from __future__ import annotations

import json
from pathlib import Path

from debench.reference import (
    confirmations,
    consensus,
    mms_check,
    problems,
    problems_reference,
    submissions,
)
from debench.reference.comparison import compare
from debench.reference.results_files import EXIT_FAILED, EXIT_OK, UsageError, read_results


def cmd_problems(args) -> int:
    if args.id is None:
        items = problems.load_all()
        if args.json:
            print(json.dumps([p.spec() for p in items], indent=1, ensure_ascii=False))
            return 0
        print(f"reference problems ({len(items)}):")
        for p in items:
            qs = ", ".join(q.name for q in p.quantities)
            print(f"  {p.id:28s} {p.chapter_label:6s}  {p.title}  [{qs}]")
        return 0
    try:
        p = problems.get(args.id)
    except problems.ProblemError as exc:
        raise UsageError(str(exc)) from None
    if args.json:
        print(json.dumps(problems_reference.reference_json(p), ensure_ascii=False))
        return 0
    if args.markdown:
        print(consensus.problem_page(p), end="")
        return 0
    spec = p.spec()
    print(f"{p.id}: {p.title} ({p.where})\n\n{p.summary}\n")
    print(f"geometry: {p.geometry}")
    if isinstance(p.boundary_conditions, str):
        print(f"boundary conditions: {p.boundary_conditions}")
    else:
        print("boundary conditions:")
        for b in p.boundary_conditions:
            print(f"  {b['boundary']}: kinematic {b['kinematic']}; electric {b['electric']}")
    if isinstance(p.loading, str):
        print(f"loading: {p.loading}")
    else:
        print(f"loading: {p.loading['path']}\ncontrolled: {p.loading['controlled']}")
    print(f"(the full page: debench problems {p.id} --markdown)")
    if p.thesis:
        print("thesis: " + ", ".join(f"{k} {v}" for k, v in p.thesis.items()))
    if p.references:
        print("references: " + "; ".join(" ".join(r.split()) for r in p.references))
    print("parameters:")
    for name, par in p.parameters.items():
        print(f"  {name} = {par.get('value')} [{par.get('units', '')}]  "
              f"{par.get('description', '')}")
    for q in p.quantities:
        acc = q.accuracy
        print(f"quantity {q.name} [{q.units}]: {q.long_name}; coordinates "
              f"{', '.join(q.coordinates)}"
              + (f" (defaults {q.defaults})" if q.defaults else ""))
        print(f"  accuracy: atol {acc.atol:g} + rtol {acc.rtol:g} |ref| ({acc.reason})")
        print(f"  discretisation: {acc.discretisation_reason}")
        for rec in confirmations.records(p.id, q):
            print(f"  confirmation: {confirmations.summary(rec)}")
    for meta in spec["provenance"]["datasets"].values():
        print(f"dataset {meta['file']} sha256 {meta['sha256']}")
    return 0


def cmd_check_submission(args) -> int:
    """``debench check --submission DIR``: the metadata against the schema (refused, each
    missing or invalid field named, exit 2), the results checksum, then the ordinary check
    at the submitter's stated tolerance (if any) and at the reference's stated accuracy;
    the exit code follows the former (0 match, 1 mismatch)."""
    if args.problem or args.file or args.rtol is not None or args.partial or args.quantity:
        raise UsageError("--submission DIR takes neither PROBLEM, FILE, --quantity, --rtol "
                         "nor --partial (the metadata states them)")
    try:
        sub = submissions.load(args.submission)
        out = submissions.check(sub)
    except submissions.SubmissionError as exc:
        raise UsageError(str(exc)) from None
    m = sub.meta
    print(f"submission {sub.folder}: {m['code']['name']} {m['code']['version']} "
          f"({m['code']['commit_or_release']}), run by {m['submitter']['name']} on "
          f"{m['submitter']['date']}; results {m['results']} sha256 verified")
    q = out.stated
    if out.declared is not None:
        print(f"at the submitter's stated tolerance ({sub.claims.get('reason')}):")
        print("  " + out.declared.summary())
    print("at the reference's stated accuracy alone:")
    print("  " + q.summary())
    prob_q = _problem_quantity(sub.problem, sub.quantity)
    if prob_q.along and len(prob_q.select):
        print(out.verdict.by_curve(prob_q.along))
    print(out.verdict.table())
    if out.claim_holds is False:
        print(f"note: the submission claims '{sub.claims['claimed']}', the check says "
              f"{'match' if out.passed else 'mismatch'}")
    return EXIT_OK if out.passed else EXIT_FAILED


def _problem_quantity(problem: str, quantity: str):
    return problems.get(problem).quantity(quantity)


def _rtol(given: list[str] | None, quantities: tuple[str, ...]):
    """``--rtol`` values: ``X`` (every quantity) or ``NAME=X`` (one quantity), repeatable:
    None, a float, or {quantity: float}."""
    if not given:
        return None
    plain, named = [], {}
    for item in given:
        name, eq, value = item.rpartition("=")
        try:
            x = float(value)
        except ValueError:
            raise UsageError(f"--rtol {item}: expected a number or NAME=number") from None
        if not eq:
            plain.append(x)
        elif name not in quantities:
            raise UsageError(f"--rtol {item}: {name!r} is not a quantity of the file "
                             f"{list(quantities)}")
        else:
            named[name] = x
    if plain and (named or len(plain) > 1):
        raise UsageError("--rtol: give one number for every quantity, or NAME=number per "
                         "quantity, not both")
    return plain[0] if plain else named


def _results_of(prob, path: Path, quantity: str | None):
    """``(quantities found, {column: values})`` of a user's file for ``prob``
    (:func:`~debench.reference.results_files.read_results`). For the manufactured-solution
    problem a table of errors per mesh level is read too: its orders are fitted and judged
    as ``debench orders`` does (the lines printed), and the fitted orders are checked."""
    if prob.id != mms_check.PROBLEM or not path.is_file() or path.suffix == ".nc" \
            or not mms_check.is_error_table(path):
        return read_results(path, quantity, prob)
    try:   # the problem is plane strain: h ~ ndof^(-1/2) for a table of ndof
        fits = mms_check.fit_error_table(path, dim=mms_check.PROBLEM_DIM)
    except (ValueError, TypeError) as exc:
        raise UsageError(
            f"{path}: a table of errors per mesh level ({exc}); `debench check` reads one "
            "with a degree column and h or ndof; otherwise fit it first: "
            f"debench orders {path} --degree P --write orders.csv, then: "
            "debench check mms_electroelastic orders.csv") from None
    print(f"{path}: errors per mesh level; fitted orders (as `debench orders {path}`):")
    for line in mms_check.order_lines(fits):
        print(f"  {line}")
    cols = mms_check.order_columns(fits)
    found = tuple(n for n in cols if n != "degree" and quantity in (None, n))
    if not found:
        raise UsageError(f"{path}: no column for quantity {quantity!r}; the fitted orders "
                         f"are {[n for n in cols if n != 'degree']}")
    return found, cols


def cmd_check(args) -> int:
    if args.submission is not None:
        return cmd_check_submission(args)
    if not args.problem or not args.file:  # argparse's own usage error (exit 2)
        args.check_parser.error("the following arguments are required: problem, file "
                                "(or --submission DIR)")
    try:
        prob = problems.get(args.problem)
    except problems.ProblemError as exc:
        raise UsageError(str(exc)) from None
    found, cols = _results_of(prob, Path(args.file), args.quantity)
    rtol = _rtol(args.rtol, found)
    qs = [prob.quantity(n) for n in found]
    coords = {c: cols[c] for c in qs[0].coordinates if c in cols}
    cov = "partial" if args.partial else "full"
    try:
        if len(qs) == 1:
            result = compare(prob.id, qs[0].name, cols[qs[0].name], coords,
                             rtol=rtol[qs[0].name] if isinstance(rtol, dict) else rtol,
                             coverage=cov)
            items = (result,)
        else:
            result = compare(prob.id, None, {q.name: cols[q.name] for q in qs}, coords,
                             rtol=rtol, coverage=cov)
            items = result.items
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    print(result.summary())
    if len(qs) > 1:
        print(result.worst())
    for q, item in zip(qs, items, strict=True):
        if q.along and len(q.select):
            print(item.by_curve(q.along))
        print(item.table())
    return EXIT_OK if result.passed else EXIT_FAILED
