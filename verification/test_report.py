"""The report: a verdict per chapter generated from the results, errata never truncated, no
raw dicts or doubled units, every figure shown (PNG linked, SVG beside it), and the
cross-check matrix measured from the datasets within the tolerances its tests assert."""

from __future__ import annotations

import re
from collections import Counter

import pytest
from debench.reference import catalogue, crosschecks, report, report_tables
from debench.reference.catalogue import Entry, Result


@pytest.fixture(scope="module")
def results():
    """Every catalogue entry with its stated value as 'ours' (no producer is run)."""
    out = []
    for e in catalogue.load():
        status = e.expected_status or "reproduced"
        out.append(Result(e, {"a": 1.0, "b": 2.0} if e.kind == "diagnosis" else e.value,
                          status, e.diagnosis or ""))
    return out


def test_report_has_a_verdict_per_chapter_and_shows_every_figure(results, tmp_path):
    figs = tmp_path / "figures"
    figs.mkdir()
    names = ["fig3_4_voltage_stretch_c0", "table5_1_uniaxial", "ch4_beyond_voltage_control",
             "unrelated_plot"]
    for n in names:
        (figs / f"{n}.png").write_bytes(b"png")
        (figs / f"{n}.svg").write_text("<svg/>")
    text = report.write_report(tmp_path, results, figures_dir=figs).read_text()
    verdicts = text.split("## Verdict per chapter")[1].split("## ")[0]
    for prefix in {r.entry.id.split(".")[0] for r in results}:
        title = report_tables.CHAPTER_TITLES.get(prefix, prefix)
        assert f"**{title}.**" in verdicts
    for n in names:
        assert f"](figures/{n}.png)" in text and f"](figures/{n}.svg)" in text
    links = re.findall(r"\]\(([^)]+\.(?:png|svg))\)", text)
    assert links and all((tmp_path / link).exists() for link in links)
    assert "{'" not in text, "a raw Python dict was printed"
    assert not re.search(r"(\S+) \1 \|", text), "a doubled unit"


def test_errata_are_never_truncated(results):
    table = report_tables.errata_table(results)
    for r in results:
        if r.entry.kind == "erratum":
            for text in (r.entry.as_printed, r.entry.corrected):
                assert " ".join(str(text).split()).replace("|", "\\|") in table


def test_fmt_renders_dicts_as_pairs_and_never_doubles_the_unit():
    assert report_tables.format_value({"x": 1.5, "y": "a"}) == "x = 1.5; y = a"
    assert report_tables.format_value("3.64 mm", "mm") == "3.64 mm"
    assert report_tables.format_value(3.64, "mm") == "3.64 mm"


def test_every_crosscheck_names_an_existing_test_and_agrees_within_its_tolerance():
    rows = crosschecks.matrix()
    assert rows
    for row in rows:
        assert crosschecks.test_exists(row.check.test), row.check.test
        if row.tolerance is not None:
            assert row.measured <= row.tolerance, (row.check.quantity, row.measured)
        else:
            assert row.measured > 0  # a diagnosis pair: the two really differ


def test_figures_save_writes_png_and_svg(tmp_path):
    from debench.reference.figures import pyplot, save

    fig, ax = pyplot().subplots()
    ax.plot([0, 1], [0, 1])
    paths = save(fig, tmp_path / "fig9_1_example.png")
    assert [p.name for p in paths] == ["fig9_1_example.png", "fig9_1_example.svg"]
    assert all(p.stat().st_size > 0 for p in paths)


def test_row_check_flags_a_deflection_compared_with_a_voltage():
    """:func:`report_tables.row_problems` can fail: a hypothesis predicting a deflection (w/t0)
    against a normalised voltage, a share against a voltage, and a boolean beside a
    number are each reported; the same hypothesis predicting a voltage is not."""
    from dataclasses import replace

    target = Entry(id="ch5.t.voltage", kind="claim", quantity="normalised critical voltage",
                   value=0.078, printed="0.078", source={"section": "5.3", "page": 1})
    deflection = Entry(id="ch5.hypothesis.t.read_off", kind="diagnosis",
                       quantity="centre deflection at the printed voltage",
                       parameters={"target": target.id, "quantity": "displacement"})
    share = replace(deflection, id="ch5.hypothesis.t.share",
                    parameters={"target": target.id, "quantity": "share"})
    good = replace(deflection, id="ch5.hypothesis.t.voltage",
                   parameters={"target": target.id, "quantity": "voltage"})
    rows = [Result(target, True, "not_reproduced", ""),
            Result(deflection, 0.0026, "unexplained", ""),
            Result(share, 0.31, "unexplained", ""), Result(good, 0.08, "unexplained", "")]
    problems = report_tables.row_problems(rows)
    assert [p.split(":")[0] for p in problems] == [
        "ch5.t.voltage", "ch5.hypothesis.t.read_off", "ch5.hypothesis.t.share"]
    assert report_tables.quantity_kind(target) == "voltage"


def test_errata_are_grouped_by_root_cause(results):
    """The errata table lists each root error first and the errata it causes after it;
    the root-cause table names the other entries that follow from a root."""
    table = report_tables.errata_table(results).splitlines()[2:]
    ids = [row.split("|")[2].strip(" `") for row in table]
    causes = [row.split("|")[1].strip(" `") for row in table]
    by_id = {r.entry.id: r.entry for r in results}
    for i, (eid, cause) in enumerate(zip(ids, causes, strict=True)):
        root = by_id[eid].root_cause
        assert cause == ("root" if root == eid else root)
        if root != eid:       # a consequence comes after its root, within its group
            j = ids.index(root)
            assert j < i and all(by_id[x].root_cause == root for x in ids[j:i + 1])
    roots = report_tables.root_cause_table(results)
    assert "`ch4.erratum.eq4_55_b`" in roots and "`ch4.ellipticity.ti_curves_well_posed`" in roots


# ----------------------------------------------------------------- counts and their tables
MARK_STATUS = {mark: status for status, mark in report_tables.STATUS_MARK.items()}
COUNTS = re.compile(r"([A-Z][^:.]*): (\d+) entr(?:y|ies): ((?:\d+ [a-z ]+?)(?:, \d+ [a-z ]+?)*)"
                    r"(?=[.;]|$)")


def _sentence_counts(text: str) -> dict[str, tuple[int, Counter]]:
    """``{label: (n, Counter(status))}`` of every counts sentence in ``text``."""
    out = {}
    for label, n, counts in COUNTS.findall(text):
        pairs = re.findall(r"(\d+) ([a-z ]+)", counts)
        out[label.lower()] = (int(n), Counter({s.strip().replace(" ", "_"): int(k)
                                                for k, s in pairs}))
    return out


def _tables(lines: list[str]) -> list[tuple[int, list[str], list[list[str]]]]:
    """Every markdown table: (index of its header line, header cells, rows of cells)."""
    out, i = [], 0
    while i < len(lines):
        if lines[i].startswith("| ") and i + 1 < len(lines) and lines[i + 1].startswith("|---"):
            head = [c.strip() for c in lines[i].strip("|").split(" | ")]
            j, rows = i + 2, []
            while j < len(lines) and lines[j].startswith("|"):
                rows.append([c.strip() for c in re.split(r"(?<!\\)\|", lines[j])[1:-1]])
                j += 1
            out.append((i, head, rows))
            i = j
        else:
            i += 1
    return out


def _status_column(head: list[str], rows: list[list[str]]) -> Counter:
    k = head.index("status")
    return Counter(MARK_STATUS[row[k]] for row in rows)


def _checked_pairs(text: str) -> int:
    """Every table with a status column is introduced by a counts sentence (the last
    non-blank line before it) whose total and counts are those of the table's rows;
    returns how many such pairs the text has."""
    lines = text.splitlines()
    pairs = 0
    for i, head, rows in _tables(lines):
        if "status" not in head or head[0] == "root error":
            continue
        before = next(line for line in reversed(lines[:i]) if line.strip())
        found = _sentence_counts(before)
        assert len(found) == 1, f"no counts sentence above the table {head}: {before!r}"
        (n, counts), = found.values()
        assert n == len(rows) and counts == _status_column(head, rows), (before, head)
        pairs += 1
    return pairs


def test_every_counts_sentence_is_that_of_the_table_below_it(results, tmp_path):
    """Each table of the report (a chapter's thesis claims, its own checks, the errata,
    the diagnoses) follows the sentence that counts it: the number of rows and the count
    of each status in its status column are the sentence's."""
    text = report.write_report(tmp_path, results, figures_dir=tmp_path / "none").read_text()
    chapters = {r.entry.id.split(".")[0] for r in results}
    assert _checked_pairs(text) >= len(chapters) + 2


def test_thesis_claims_and_own_checks_are_counted_apart(results, tmp_path):
    """The verdict of each chapter counts its thesis claims and its own checks (kind
    ``derived``: cross-checks of our models) as the chapter's two tables do, and names
    exactly the rows those tables mark not reproduced; an own check is never counted
    among the thesis claims."""
    text = report.write_report(tmp_path, results, figures_dir=tmp_path / "none").read_text()
    verdicts = text.split("## Verdict per chapter")[1].split("\n## ")[0]
    sections = text.split("\n## ")
    by_id = {r.entry.id: r.entry for r in results}
    for prefix in {r.entry.id.split(".")[0] for r in results}:
        title = report_tables.CHAPTER_TITLES.get(prefix, prefix)
        verdict = next(v for v in verdicts.split("\n\n") if v.startswith(f"**{title}.**"))
        section = next(s for s in sections if s.startswith(f"{title}\n"))
        tables = {head[1]: (head, rows) for _, head, rows in _tables(section.splitlines())
                  if "status" in head}
        said = _sentence_counts(verdict)
        for group, column in (("claims", "thesis claim"), ("own checks", "check")):
            chunk = report_tables.in_group([r for r in results
                                     if r.entry.id.split(".")[0] == prefix], group)
            label = report_tables.GROUP_LABELS[group]
            if not chunk:
                assert column not in tables and label not in said
                continue
            head, rows = tables[column]
            assert said[label] == (len(rows), _status_column(head, rows)), (prefix, group)
            kinds = {by_id[row[0].strip("`")].kind for row in rows}
            assert kinds <= ({"claim", "literature"} if group == "claims" else {"derived"})
            missed = {row[0].strip("`") for row in rows
                      if MARK_STATUS[row[head.index("status")]] == "not_reproduced"}
            lead = ("Not reproduced: " if group == "claims" else
                    "Own checks not reproduced (our implementations disagree): ")
            named = verdict.split(lead)[1].split(". ")[0] if lead in verdict else ""
            assert set(re.findall(r"`([^`]+)`", named)) == missed, (prefix, group)


def test_errata_counts_root_errors_and_the_errata_page_agree_with_their_tables(results,
                                                                              tmp_path):
    """The errata sentence counts confirmed, refuted and editorial apart (refuted ones
    are said to be no errata), its root errors are the rows of the root-cause table, and
    the documentation's errata page opens with the same counts as its table."""
    from verification._loaders import load_script

    sentence = report.errata_sentence(results)
    table = report_tables.errata_table(results).splitlines()
    (n, counts), = _sentence_counts(sentence).values()
    _, head, rows = _tables(table)[0]
    assert (n, counts) == (len(rows), _status_column(head, rows))
    assert counts["refuted"] == 0 or "not errata of the thesis" in sentence
    roots = report_tables.root_cause_table(results).splitlines()[2:]
    assert f"By root error ({len(roots)}):" in sentence
    listed = re.findall(r"`([^`]+)`(?: \(with [^)]*\))?", sentence.split("By root error")[1])
    assert listed == [row.split("|")[1].strip(" `") for row in roots]
    pages = load_script("docs/_ext/debench_pages.py")
    pages.OUT = tmp_path
    pages.errata_page(results)
    page = (tmp_path / "errata.md").read_text()
    assert sentence in page and "errata of the thesis, from" not in page
    assert _checked_pairs(page) == 1


def test_readme_tables_count_what_their_sentences_say(results):
    """The README block: the thesis claims' table and the table of own checks, errata,
    diagnoses and assumptions each sum, column by column, to the counts of the sentence
    above it; no table mixes thesis claims with own checks."""
    lines = report.readme_block(results).splitlines()
    labels = {v: k for k, v in report_tables.GROUP_LABELS.items()}
    tables = _tables(lines)
    assert len(tables) == len(report.README_TABLES)
    for (i, head, rows), groups in zip(tables, report.README_TABLES, strict=True):
        said = _sentence_counts(next(line for line in reversed(lines[:i]) if line.strip()))
        assert {labels[label] for label in said} == set(groups)
        total = Counter()
        for k, cell in enumerate(head[2:], start=2):
            group, _, status = cell.rpartition(": ")
            total[(group or groups[0], status.replace(" ", "_"))] = sum(
                int(row[k]) for row in rows)
        for label, (n, counts) in said.items():
            group = labels[label]
            kinds = {"claims": ("claim", "literature"), "own checks": ("derived",)}
            if group in kinds:  # the thesis' claims apart from our own checks
                assert n == sum(r.entry.kind in kinds[group] for r in results)
            assert counts == Counter({s: v for (g, s), v in total.items() if g == group})
            assert n == sum(counts.values())
        assert sum(int(row[1]) for row in rows) == sum(n for n, _ in said.values())


def test_crosscheck_sentence_counts_the_matrix_rows(results):
    """"K of the N pairs ... agree" counts the rows of the matrix below it, and the
    sentence after it counts the catalogue's own checks and names those not reproduced."""
    lines = "\n".join(report.crosscheck_section(results=results)).splitlines()
    _, head, rows = _tables(lines)[0]
    judged = [row[head.index("verdict")] for row in rows
              if row[head.index("tolerance")] != "—"]
    agree, of = map(int, re.match(r"(\d+) of the (\d+) pairs", lines[2]).groups())
    assert (agree, of) == (judged.count("agree"), len(judged))
    own = report_tables.in_group(results, "own checks")
    after = next(line for line in lines if line.startswith("Beyond this matrix"))
    (n, counts), = _sentence_counts(after).values()
    assert (n, counts) == (len(own), report_tables.status_counts(own))
    for r in own:
        assert (f"`{r.entry.id}`" in after) == (r.status == "not_reproduced"), r.entry.id


def test_readable_formats_numbers_mappings_and_sequences_for_prose():
    """:func:`catalogue.readable`: numpy scalars and arrays as numbers, a mapping as
    ``key = value`` pairs, nested sequences in parentheses, floats to the digits asked."""
    import numpy as np

    assert catalogue.readable({"derived": 1.0, "printed": 1.0,
                               "literal": 0.9999999994444345}, 11) == \
        "derived = 1, printed = 1, literal = 0.99999999944"
    assert catalogue.readable({"max_area": 2.085148975471975,
                               "thin_extensional": np.float64(2.334815259489528)}) == \
        "max_area = 2.08515, thin_extensional = 2.33482"
    assert catalogue.readable([np.array([1.5, 2.0]), (np.int64(3), True, "x")]) == \
        "(1.5, 2), (3, True, x)"


#: references a verdict may type (they name places, not values): an equation number in
#: parentheses, a chapter, table, figure or section number
VERDICT_REFERENCES = re.compile(r"\(\d+\.\d+\)|\b(?:Chapter|Table|Fig\.|Figure|Section|§)\s*"
                                r"\d+(?:\.\d+)*")


def test_verdict_types_no_number():
    """Every number of the verdict in brief (reference/verdict.md) comes from a placeholder
    filled from the computed records: outside placeholders only equation, chapter, table,
    figure and section numbers are typed."""
    text = report.PLACEHOLDER.sub("", report.verdict_template())
    typed = re.findall(r".{0,30}\d.{0,30}", VERDICT_REFERENCES.sub("", text))
    assert not typed, f"numbers typed in reference/verdict.md: {typed}"


def test_verdict_placeholders_name_catalogue_entries(results):
    """Every placeholder of the verdict names an entry, a field, a count, errata or a
    consensus (a bad one raises VerdictError); with the stated values as ours (the fixture)
    it renders with no Python repr and no placeholder left."""
    text = report.verdict_markdown(results)
    assert "{{" not in text and "}}" not in text
    assert "np.float64(" not in text and "{'" not in text
    assert report.VERDICT_START not in text


def test_verdict_placeholder_errors_are_raised(results, tmp_path):
    bad = tmp_path / "verdict.md"
    for body in ("{{ ch3.no_such_entry }}", "{{ count nonsense }}",
                 "{{ ch3.loss_of_tension.stretch_lamP_3.colour }}"):
        bad.write_text(body)
        with pytest.raises(report.VerdictError):
            report.verdict_markdown(results, bad)
    bad.write_text("{{ ch3.loss_of_tension.stretch_lamP_3.details.no_such_key }}")
    assert "not computed" in report.verdict_markdown(results, bad)


def test_consensus_sentence_says_within_only_of_values_that_are(monkeypatch):
    """The verdict's sentence on other codes counts the values within the reference's
    stated accuracy from the consensus records; none within reads "0 of 2"."""
    from debench.reference import consensus

    rows = [consensus.Row(code=f"{c} 1.0 (x)", folder="f", selection="case=a", value=v,
                          reference=1.0, error=v - 1.0, tolerance_stated=1e-9,
                          within_stated=False, within_declared=True,
                          tolerance_declared=1e-3, points=1)
            for c, v in (("A", 1.0001), ("B", 0.9999))]
    table = consensus.Table("p", "q", "1", False, rows)
    monkeypatch.setattr(consensus, "tables", lambda root=None: [table])
    text = report.consensus_sentence("p", "q")
    assert "0 of 2 lie within the reference's stated accuracy" in text
    assert "2 of 2 within the accuracy their submitters state" in text
    assert "agree" not in text
    assert report.consensus_sentence("p", "other").startswith("no curated submission")
