#!/usr/bin/env python3
"""No function in src/ longer than 100 lines (docs/developer/testing.md).

    check_function_length.py SOURCE_DIR [--limit N] [--extra FILE ...] [--list]

Reads every .cpp and .hpp below SOURCE_DIR/src (and the --extra files) and
finds the bodies of functions: a brace at namespace or class level whose
heading has a parameter list and no '=' (a lambda or a table given to a
variable is not a function of its own; a lambda inside a function counts
with it). Comments, string and character literals and preprocessor lines
are blanked first, so their braces do not count. A function's length is
its lines from the first line of its heading to its closing brace.

Exit 1, naming each function with its file, line and length, when one is
longer than the limit and not in ALLOWED at exactly its length; also when
an entry of ALLOWED is no longer over the limit or shorter than its
allowance. --list prints every function over the limit and exits 0.
"""
import argparse
import os
import re
import sys

# Functions allowed over the limit for a while, each at its length (none
# now). The list may only shrink: a function that grows, a new long one, or
# an entry left behind when its function got shorter fails the check.
ALLOWED = {
}

IDENT = re.compile(r"[A-Za-z_~][A-Za-z0-9_]*")
KEYWORDS_NOT_NAMES = {"if", "for", "while", "switch", "catch", "return", "sizeof", "decltype",
                      "noexcept", "alignas", "alignof", "static_assert", "requires"}


def blank(text):
    """The text with comments, string and character literals and
    preprocessor lines replaced by spaces (newlines kept)."""
    out = list(text)
    i, n = 0, len(text)
    line_start = True

    def wipe(a, b):
        for k in range(a, b):
            if out[k] != "\n":
                out[k] = " "

    while i < n:
        c = text[i]
        if line_start and c in " \t":
            i += 1
            continue
        if line_start and c == "#":
            j = i
            while j < n and (text[j] != "\n" or text[j - 1] == "\\"):
                j += 1
            wipe(i, j)
            i = j
            continue
        line_start = c == "\n"
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            wipe(i, j)
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            wipe(i, j)
            i = j
        elif c == 'R' and text.startswith('R"', i) and not (i and (text[i - 1].isalnum() or text[i - 1] == "_")):
            open_paren = text.find("(", i)
            delim = ")" + text[i + 2:open_paren] + '"'
            j = text.find(delim, open_paren)
            j = n if j < 0 else j + len(delim)
            wipe(i, j)
            i = j
        elif c == '"' or (c == "'" and not (i and text[i - 1].isalnum())):
            # A quote after a letter or digit is a digit separator (1'000).
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            wipe(i, j + 1)
            i = j + 1
        else:
            i += 1
    return "".join(out)


def top_level(heading):
    """The heading with every (...), [...] and {...} group emptied."""
    out, depth = [], 0
    for c in heading:
        if c in "([{":
            if depth == 0:
                out.append(c)
            depth += 1
        elif c in ")]}":
            depth -= 1
            if depth == 0:
                out.append(c)
        elif depth == 0:
            out.append(c)
    return "".join(out)


def function_name(heading):
    """The (qualified) name before the parameter list, or None."""
    flat = top_level(heading)
    flat = re.sub(r"operator\s*(\(\)|[^\sA-Za-z_(]+)\s*\(", lambda m: "operator" + re.sub(r"\W", "_", m.group(1)) + "(", flat)
    for m in re.finditer(r"((?:[A-Za-z_~][A-Za-z0-9_]*\s*(?:<[^<>;{}()]*>)?\s*::\s*)*~?[A-Za-z_][A-Za-z0-9_]*)\s*\(", flat):
        name = re.sub(r"\s+", "", m.group(1))
        last = name.split("::")[-1]
        if last not in KEYWORDS_NOT_NAMES:
            return name
    return None


def is_function(heading):
    flat = top_level(heading)
    flat = re.sub(r"operator\s*[^\sA-Za-z_(]*", "operator", flat)
    flat = re.sub(r"[=!<>]=", "", flat)
    return "(" in flat and "=" not in flat


def scan(text):
    """Yields (name, first line, last line) of every function body."""
    code = blank(text)
    line_of = [0] * (len(code) + 1)
    ln = 1
    for k, c in enumerate(code):
        line_of[k] = ln
        if c == "\n":
            ln += 1
    line_of[len(code)] = ln

    def match(k):
        depth = 0
        while k < len(code):
            if code[k] == "{":
                depth += 1
            elif code[k] == "}":
                depth -= 1
                if depth == 0:
                    return k
            k += 1
        return len(code) - 1

    def block(start, end, scope):
        """Walks a namespace or class body between start and end."""
        head = start
        k = start
        while k < end:
            c = code[k]
            if c in ";}":
                head = k + 1
            elif c == "(":
                depth = 0
                while k < end:
                    depth += code[k] == "("
                    depth -= code[k] == ")"
                    if depth == 0:
                        break
                    k += 1
            elif c == "{":
                heading = code[head:k]
                words = set(IDENT.findall(re.sub(r"template\s*<[^{;]*?>\s*", " ", heading)))
                close = match(k)
                before = heading.rstrip()
                in_init = re.search(r"\)\s*[A-Za-z_&\s]*:(?!:)", top_level(heading))
                if in_init and before and (before[-1].isalnum() or before[-1] in "_>"):
                    k = close  # a member's braced initialiser in a constructor's list
                elif "namespace" in words or ("extern" in words and before.endswith("extern")):
                    yield from block(k + 1, close, scope)
                    head = close + 1
                elif words & {"class", "struct", "union"} and "(" not in top_level(heading):
                    yield from block(k + 1, close, scope)
                    head = close + 1
                elif "enum" not in words and is_function(heading):
                    name = function_name(heading) or "?"
                    first = head + len(heading) - len(heading.lstrip())
                    yield name, line_of[first], line_of[close]
                    head = close + 1
                k = close
            k += 1

    yield from block(0, len(code), "")


def files_below(root):
    for folder, dirs, names in os.walk(os.path.join(root, "src")):
        dirs.sort()
        for name in sorted(names):
            if name.endswith((".cpp", ".hpp")):
                yield os.path.join(folder, name)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("source_dir")
    ap.add_argument("--limit", type=int, default=100)
    ap.add_argument("--extra", nargs="*", default=[], help="more files to check")
    ap.add_argument("--list", action="store_true", help="print every long function, exit 0")
    args = ap.parse_args()
    root = os.path.abspath(args.source_dir)
    paths = list(files_below(root)) + [os.path.abspath(p) for p in args.extra]
    over = {}  # "file:name" -> (first line, length)
    for path in paths:
        rel = os.path.relpath(path, root)
        with open(path, encoding="utf-8") as f:
            text = f.read()
        for name, first, last in scan(text):
            if last - first + 1 > args.limit:
                over[f"{rel}:{name}"] = (first, last - first + 1)
    if args.list:
        for key, (first, length) in over.items():
            rel, name = key.split(":", 1)
            note = " (allowed for now)" if key in ALLOWED else ""
            print(f"{rel}:{first}: {name}: {length} lines{note}")
        return 0
    bad = 0
    for key, (first, length) in over.items():
        rel, name = key.split(":", 1)
        allowance = ALLOWED.get(key)
        if allowance is None:
            print(f"{rel}:{first}: {name} has {length} lines, more than {args.limit}")
        elif length > allowance:
            print(f"{rel}:{first}: {name} has {length} lines, more than the {allowance} "
                  f"it is allowed for now")
        elif length < allowance:
            print(f"{rel}:{first}: {name} has {length} lines now: lower its allowance in "
                  f"{os.path.basename(__file__)} from {allowance} to {length}")
        else:
            continue
        bad += 1
    for key in sorted(set(ALLOWED) - set(over)):
        print(f"{key}: no longer over {args.limit} lines (or gone): take it off the "
              f"allow-list of {os.path.basename(__file__)}")
        bad += 1
    if bad:
        return 1
    print(f"check_function_length: no function over {args.limit} lines in {len(paths)} files "
          f"but the {len(ALLOWED)} allowed for now")
    return 0


if __name__ == "__main__":
    sys.exit(main())
