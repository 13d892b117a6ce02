"""The README and docs/ link only to files and headings that exist, and the user
pages carry no history: a moved or renamed page or heading fails here."""
import os
import re

import pytest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)\)")
FENCE = re.compile(r"^(```|~~~)")


def markdown_pages():
    pages = [os.path.join(ROOT, "README.md")]
    for folder, _, files in os.walk(os.path.join(ROOT, "docs")):
        pages += [os.path.join(folder, f) for f in sorted(files) if f.endswith(".md")]
    return pages


def prose_lines(path):
    """(number, line) of a page outside its fenced code blocks."""
    fenced = False
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            if FENCE.match(line.strip()):
                fenced = not fenced
            elif not fenced:
                yield number, line


def anchor(heading):
    """The anchor GitHub gives a heading: lower case, punctuation dropped,
    spaces to hyphens (letters of any script kept)."""
    text = re.sub(r"[^\w\- ]", "", heading.strip().lower())
    return text.replace(" ", "-")


def anchors(path):
    seen, result = {}, set()
    for _, line in prose_lines(path):
        match = re.match(r"#{1,6} (.*)", line)
        if not match:
            continue
        base = anchor(match.group(1))
        count = seen.get(base, 0)
        seen[base] = count + 1
        result.add(base if count == 0 else "%s-%d" % (base, count))
    return result


def broken_links(path):
    problems = []
    for number, line in prose_lines(path):
        for target in LINK.findall(line):
            if re.match(r"[a-z]+:", target):  # http:, https:, mailto:
                continue
            file_part, _, fragment = target.partition("#")
            resolved = os.path.normpath(os.path.join(os.path.dirname(path), file_part)) \
                if file_part else path
            where = "%s:%d: %s" % (os.path.relpath(path, ROOT), number, target)
            if not os.path.exists(resolved):
                problems.append(where + " (no such file)")
            elif fragment and resolved.endswith(".md") and fragment not in anchors(resolved):
                problems.append(where + " (no such heading)")
    return problems


def missing_mentions(path):
    """Pages named in the prose (`docs/fracture.md`, `theory.md`) that exist
    neither beside the page, nor from the root, nor under docs/."""
    problems = []
    for number, line in prose_lines(path):
        for name in re.findall(r"(?<![\w/.(-])((?:[\w-]+/)*[\w-]+\.md)\b", line):
            if re.match(r"(results|[A-Z_]+)/", name):  # a result folder, a placeholder
                continue
            places = [os.path.dirname(path), ROOT, os.path.join(ROOT, "docs")]
            if not any(os.path.exists(os.path.join(p, name)) for p in places):
                problems.append("%s:%d: %s" % (os.path.relpath(path, ROOT), number, name))
    return problems


def test_every_page_named_exists():
    problems = [p for page in markdown_pages() for p in missing_mentions(page)]
    assert not problems, "\n".join(problems)


def test_every_link_resolves():
    problems = [p for page in markdown_pages() for p in broken_links(page)]
    assert not problems, "\n".join(problems)


@pytest.mark.parametrize("page", [p for p in markdown_pages()
                                  if os.sep + "notes" + os.sep not in p],
                         ids=lambda p: os.path.relpath(p, ROOT))
def test_user_pages_name_no_issue(page):
    """History (issue numbers, work in progress) belongs to docs/notes/ and git."""
    found = ["%d: %s" % (n, line.strip()) for n, line in prose_lines(page)
             if re.search(r"\bissues? \d+|\bin progress\b", line, re.IGNORECASE)]
    assert not found, "\n".join(found)


DATED_FOLDERS = ("guide", "model", "reference", "developer")
ISO_DATE = re.compile(r"\b\d{4}-\d{2}-\d{2}\b")


@pytest.mark.parametrize("page", [p for p in markdown_pages()
                                  if os.path.relpath(p, os.path.join(ROOT, "docs")).split(os.sep)[0]
                                  in DATED_FOLDERS],
                         ids=lambda p: os.path.relpath(p, ROOT))
def test_reference_pages_carry_no_dates(page):
    """The guide, model, reference and developer pages say what is true now:
    a dated measurement goes to docs/notes/ (linked from the page)."""
    with open(page, encoding="utf-8") as f:
        found = ["%d: %s" % (n, line.strip()) for n, line in enumerate(f, 1)
                 if ISO_DATE.search(line)]
    assert not found, "\n".join(found)


# A reference page stays short enough to read through: past this many lines
# it is split by purpose into pages of the same folder, the first of them the
# entry with a summary of and a link to each of the others.  docs/notes/ is
# history and exempt.
MAX_PAGE_LINES = 450


def reference_pages():
    return [p for p in markdown_pages()
            if os.path.relpath(p, ROOT).startswith("docs" + os.sep)
            and os.sep + "notes" + os.sep not in p]


@pytest.mark.parametrize("page", reference_pages(), ids=lambda p: os.path.relpath(p, ROOT))
def test_reference_pages_are_short(page):
    name = os.path.relpath(page, ROOT).replace(os.sep, "/")
    with open(page, encoding="utf-8") as f:
        lines = sum(1 for _ in f)
    assert lines <= MAX_PAGE_LINES, (
        "%s has %d lines, more than %d: split it by purpose into pages of its folder, "
        "this one the entry with a summary and a link to each" % (name, lines, MAX_PAGE_LINES))


# The results pages explain in words that do not date; what was measured
# when sits in one block per topic (a "### Measured" heading, to the next
# heading of its level or above) that links to its write-up in docs/notes/.
# The results pages are the pages at the top of docs/ (benchmarks.md and the
# pages split from it, convergence.md, paper.md, scaling.md, …).
RESULTS_PAGES = sorted(f for f in os.listdir(os.path.join(ROOT, "docs")) if f.endswith(".md"))
HEADING = re.compile(r"(#{1,6}) (.*)")
DAY_WORDS = re.compile(r"\b(today|today's|yesterday|that day|this week|this morning)\b",
                       re.IGNORECASE)
NOTES_LINK = re.compile(r"\]\((\.\./)?notes/[^)]+\)")


def measured_blocks(lines):
    """Problems of a results page's text (a list of lines): ISO dates and
    words like "today" outside a Measured block, a block without a link to
    docs/notes/, two blocks in one topic (a "##" section)."""
    problems, blocks_in_topic = [], 0
    block = None  # (level, first line number, has a notes link)
    fenced = False

    def close():
        if block and not block[2]:
            problems.append("%d: a Measured block without a link to docs/notes/" % block[1])

    for number, line in enumerate(lines, 1):
        if FENCE.match(line.strip()):
            fenced = not fenced
        heading = None if fenced else HEADING.match(line)
        if heading:
            level = len(heading.group(1))
            if block and level <= block[0]:
                close()
                block = None
            if level <= 2:
                blocks_in_topic = 0
            if heading.group(2).startswith("Measured"):
                blocks_in_topic += 1
                if blocks_in_topic > 1:
                    problems.append("%d: a second Measured block in one topic" % number)
                block = (level, number, False)
        if block:
            if NOTES_LINK.search(line):
                block = (block[0], block[1], True)
            continue
        if ISO_DATE.search(line):
            problems.append("%d: a date outside a Measured block: %s" % (number, line.strip()))
        if DAY_WORDS.search(line):
            problems.append("%d: a word that dates outside a Measured block: %s"
                            % (number, line.strip()))
    close()
    return problems


@pytest.mark.parametrize("page", RESULTS_PAGES)
def test_results_pages_keep_dates_in_measured_blocks(page):
    with open(os.path.join(ROOT, "docs", page), encoding="utf-8") as f:
        problems = measured_blocks(f.read().splitlines())
    assert not problems, "\n".join(problems)


def test_measured_block_rule():
    ok = ["## Topic", "Timeless words.", "### Measured (2026-11-27)",
          "Figures of that day ([notes](notes/x.md)).", "## Next", "More words."]
    assert measured_blocks(ok) == []
    assert measured_blocks(["## T", "measured 2026-11-27"])  # outside a block
    assert measured_blocks(["## T", "as today"])
    assert measured_blocks(["## T", "### Measured", "2026-11-27"])  # no notes link
    assert measured_blocks(["## T", "### Measured", "[n](notes/a.md)", "### Other",
                            "2026-11-27"])  # the block ended
    assert measured_blocks(["## T", "### Measured", "[n](notes/a.md)", "### Measured again",
                            "[n](notes/b.md)"])  # two in a topic


def test_date_rule():
    assert ISO_DATE.search("measured 2026-11-26 on")
    assert not ISO_DATE.search("seeds 1-3, 10-20 s, 2026-11")


def test_anchor_rule():
    assert anchor("Decided solves (`-fracture_decision_safety`)") == \
        "decided-solves--fracture_decision_safety"
    assert anchor("Fracture at 10⁷ bonds") == "fracture-at-10⁷-bonds"
    assert anchor("The paper against ours") == "the-paper-against-ours"


# Options the user pages name on purpose although no program reads them.
# (the typo of the unknown-option example; the extension example's own options)
NOT_OPTIONS = {"-lattice_node", "-fracture_counted_label", "-fracture_weakest_count",
               "-solver_counted_applications"}
PETSC_OPTION = re.compile(r"-(ksp|pc|mg|mat|log|memory|fallback|vec|options|patch_ksp|patch_pc|"
                          r"deflation_coarse)_")


def test_every_option_named_exists():
    """An option named on a user page is one the programs read (their -help,
    as written to docs/reference/options.md) or one of PETSc's."""
    with open(os.path.join(ROOT, "docs", "reference", "options.md"), encoding="utf-8") as f:
        known = set(re.findall(r"\| `(-[a-z0-9_]+)` \|", f.read()))
    assert len(known) > 100
    unknown = []
    for page in markdown_pages():
        if os.sep + "notes" + os.sep in page:
            continue
        with open(page, encoding="utf-8") as f:
            for number, line in enumerate(f, 1):
                for name in re.findall(r"(?<![\w-])(-[a-z][a-z0-9]*_[a-z0-9_]*)", line):
                    if name in known or name in NOT_OPTIONS or PETSC_OPTION.match(name + "_") \
                            or name.endswith("_"):
                        continue
                    unknown.append("%s:%d: %s" % (os.path.relpath(page, ROOT), number, name))
    assert not unknown, "\n".join(unknown)
