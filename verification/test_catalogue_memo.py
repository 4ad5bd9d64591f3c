"""The catalogue files are parsed once per process and content (:func:`catalogue.load`).

Producers resolve target ids with :func:`catalogue.by_id` and the CLI, the report and the
builders load the catalogue again; the memo must make these calls cheap without ever
serving a stale catalogue: an edit of a TOML file is seen by the next call.
"""

from __future__ import annotations

import pytest
from debench.reference import catalogue

ENTRY = ('[[entry]]\nid = "ch3.memo.a"\nkind = "claim"\nquantity = "q"\nvalue = {value}\n'
         'printed = "{value}"\nsource = {{section = "3"}}\n')


def _counting_parse(monkeypatch):
    calls = []
    parse = catalogue.parse_files

    def counted(files):
        calls.append(tuple(name for name, _ in files))
        return parse(files)

    monkeypatch.setattr(catalogue, "parse_files", counted)
    return calls


def test_repeated_loads_parse_the_files_once(tmp_path, monkeypatch):
    """Two loads and a by_id of an unchanged directory parse its files once and give
    equal entries, each call a list of its own."""
    (tmp_path / "a.toml").write_text(ENTRY.format(value=1.5))
    calls = _counting_parse(monkeypatch)
    first = catalogue.load(tmp_path)
    second = catalogue.load(tmp_path)
    ids = catalogue.by_id(catalogue.load(tmp_path))
    assert len(calls) == 1
    assert first == second and first is not second
    assert ids["ch3.memo.a"].value == 1.5


def test_an_edited_catalogue_file_is_seen(tmp_path, monkeypatch):
    """An edit of a TOML file (same name, same size, within the same mtime tick) is seen
    by the next load: the memo is keyed on the files' content."""
    path = tmp_path / "a.toml"
    path.write_text(ENTRY.format(value=1.5))
    calls = _counting_parse(monkeypatch)
    assert catalogue.load(tmp_path)[0].value == 1.5
    path.write_text(ENTRY.format(value=2.5))
    assert catalogue.load(tmp_path)[0].value == 2.5
    (tmp_path / "b.toml").write_text(ENTRY.format(value=3.5).replace("memo.a", "memo.b"))
    assert [e.id for e in catalogue.load(tmp_path)] == ["ch3.memo.a", "ch3.memo.b"]
    assert len(calls) == 3


def test_a_malformed_edit_is_rejected_after_a_good_load(tmp_path):
    """The memo never hides a broken file: a load after a bad edit raises."""
    path = tmp_path / "a.toml"
    path.write_text(ENTRY.format(value=1.5))
    catalogue.load(tmp_path)
    path.write_text(ENTRY.format(value=1.5).replace('"claim"', '"rumour"'))
    with pytest.raises(catalogue.CatalogueError, match="kind"):
        catalogue.load(tmp_path)
