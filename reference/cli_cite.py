"""``debench cite`` (:mod:`debench.reference.cli`): a citation of a catalogue entry,
problem or dataset. Apart from the other users' subcommands, so that printing a citation
loads no numerics."""

from __future__ import annotations

import sys

from debench.reference import cite
from debench.reference.results_files import UsageError


def cmd_cite(args) -> int:
    try:
        print(cite.render(args.id, args.format))
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    return 0


def cmd_cite_naming_others(args) -> int:
    """``debench cite``: the citation on stdout and, when the id names more than one thing
    (a problem and a dataset of the same name), which one was cited and how to cite the
    other on stderr (:func:`debench.reference.cite.ambiguity`)."""
    code = cmd_cite(args)
    note = cite.ambiguity(args.id)
    if note:
        print(f"debench: note: {note}", file=sys.stderr)
    return code
