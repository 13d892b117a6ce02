"""docs/notes/README.md lists every note once, with a status that is one of
three (current, superseded by an existing page or note, history), and a
note marked current is one a page outside the notes links to."""
import os
import re

from conftest import markdown_table
from test_docs_links import markdown_pages

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
NOTES = os.path.join(ROOT, "docs", "notes")
INDEX = "README.md"
LINK = re.compile(r"\[[^\]]*\]\(([^)\s]+)\)")
SUPERSEDED = re.compile(r"superseded by \[[^\]]*\]\(([^)\s]+)\)")


def linking_pages():
    """The text of README.md and of every page under docs/ but the notes."""
    texts = []
    for path in markdown_pages():
        if os.path.dirname(path) != NOTES:
            with open(path, encoding="utf-8") as f:
                texts.append(f.read())
    return texts


def index_problems(rows, notes_dir, pages):
    """What is wrong with the index rows (lists of cells: note, status, what
    it holds) of the notes in `notes_dir`, given the text of the pages
    outside the notes."""
    problems, listed = [], []
    for cells in rows:
        links = LINK.findall(cells[0])
        if len(links) != 1 or len(cells) != 3:
            problems.append("a row is not [note](note) | status | what it holds: %s"
                            % " | ".join(cells))
            continue
        name, status = links[0], cells[1]
        listed.append(name)
        if not os.path.isfile(os.path.join(notes_dir, name)):
            problems.append("%s is listed but no such note exists" % name)
        superseded = SUPERSEDED.fullmatch(status)
        if superseded:
            target = superseded.group(1).partition("#")[0]
            if not os.path.exists(os.path.normpath(os.path.join(notes_dir, target))):
                problems.append("%s: superseded by %s, which does not exist" % (name, target))
        elif status not in ("current", "history"):
            problems.append("%s: the status %r is none of current, superseded by [...](...), "
                            "history" % (name, status))
        if status == "current" and not any(re.search(r"notes/%s\b" % re.escape(name), text)
                                           for text in pages):
            problems.append("%s: current, but no page outside the notes links to it" % name)
        if not cells[2]:
            problems.append("%s: no sentence of what it holds" % name)
    notes = sorted(f for f in os.listdir(notes_dir) if f.endswith(".md") and f != INDEX)
    problems += ["%s is missing from the index" % n for n in notes if n not in listed]
    problems += ["%s is listed twice" % n for n in sorted(set(listed)) if listed.count(n) > 1]
    return problems


def test_every_note_indexed_with_a_status():
    rows = markdown_table(os.path.join(NOTES, INDEX), "note")
    problems = index_problems(rows, NOTES, linking_pages())
    assert not problems, "\n".join(problems)


def test_index_rule_catches_each_fault(tmp_path):
    for name in ("a.md", "b.md", "c.md", "unlisted.md"):
        (tmp_path / name).write_text("# note\n")
    pages = ["see [a](notes/a.md)"]
    good = [["[a.md](a.md)", "current", "A."],
            ["[b.md](b.md)", "superseded by [a.md](a.md)", "B."],
            ["[c.md](c.md)", "history", "C."],
            ["[unlisted.md](unlisted.md)", "history", "U."]]
    assert index_problems(good, str(tmp_path), pages) == []
    wrong = [["[a.md](a.md)", "current", "A."],
             ["[b.md](b.md)", "superseded by [gone](../gone.md)", "B."],
             ["[c.md](c.md)", "old", "C."],
             ["[d.md](d.md)", "history", "D."]]
    problems = "\n".join(index_problems(wrong, str(tmp_path), []))
    for part in ("a.md: current, but no page", "b.md: superseded by ../gone.md",
                 "c.md: the status 'old'", "d.md is listed but no such note",
                 "unlisted.md is missing from the index"):
        assert part in problems
