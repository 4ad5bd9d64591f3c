"""The docs' peers page: the submission guide and the consensus table are shown where the
repository has them, said absent where it does not, and any other failure fails the build
(fast; the site itself is built by ``test_docs.py``, opt-in with ``--docs``)."""

from __future__ import annotations

import sys
import types

import pytest

from verification._loaders import load_script


@pytest.fixture
def pages(tmp_path, monkeypatch):
    mod = load_script("docs/_ext/debench_pages.py")
    monkeypatch.setattr(mod, "OUT", tmp_path / "generated")
    monkeypatch.setattr(mod, "ROOT", tmp_path)
    return mod


def _page(pages) -> str:
    pages.peers_page()
    return (pages.OUT / "peers.md").read_text()


def test_absent_guide_and_consensus_are_said_absent(pages, monkeypatch):
    monkeypatch.setitem(sys.modules, "debench.reference.consensus", None)  # import fails
    text = _page(pages)
    assert "has no `peers/README.md`" in text and "has no consensus table" in text


def test_present_guide_and_consensus_are_shown(pages, monkeypatch):
    (pages.ROOT / "peers").mkdir()
    (pages.ROOT / "peers" / "README.md").write_text("# Submitting\n")
    fake = types.ModuleType("debench.reference.consensus")
    fake.consensus_markdown = lambda: "| code | value |\n|---|---|\n| peer | 0.22 |"
    monkeypatch.setitem(sys.modules, "debench.reference.consensus", fake)
    text = _page(pages)
    assert "{include} ../../peers/README.md" in text and "| peer | 0.22 |" in text


def test_consensus_without_a_known_function_fails(pages, monkeypatch):
    monkeypatch.setitem(sys.modules, "debench.reference.consensus",
                        types.ModuleType("debench.reference.consensus"))
    with pytest.raises(RuntimeError, match="consensus"):
        _page(pages)


def test_a_failing_consensus_table_fails(pages, monkeypatch):
    fake = types.ModuleType("debench.reference.consensus")

    def broken():
        raise ValueError("a submission does not match its checksum")

    fake.consensus_markdown = broken
    monkeypatch.setitem(sys.modules, "debench.reference.consensus", fake)
    with pytest.raises(ValueError, match="checksum"):
        _page(pages)
