"""The module table of docs/developer/architecture.md says what the code
and the root CMakeLists.txt say: the same modules in the same order, each
row naming its module's headers, its declared dependencies and external
libraries, and only files that exist in it."""
import os
import re

import pytest

from conftest import markdown_table

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
PAGE = os.path.join(ROOT, "docs", "developer", "architecture.md")
# Rows of the table that are no module of src/ (the programs and the study
# tools above the modules).
NOT_MODULES = ("drivers", "study")
CODE = re.compile(r"`([^`]+)`")


def declared_modules(cmake_text):
    """{module: (dependencies, external libraries)} in the order of the
    lem_module() lines; a library is named by its namespace (MPI for
    MPI::MPI_CXX), and those linked to a module's target on a line of their
    own count too."""
    modules = {}
    for name, args in re.findall(r"^lem_module\((\w+)([^)]*)\)", cmake_text, re.M):
        lists, current = {"DEPENDS": [], "LIBS": []}, None
        for word in args.split():
            if word in lists:
                current = word
            elif current:
                lists[current].append(word)
        modules[name] = (lists["DEPENDS"], [lib.split("::")[0] for lib in lists["LIBS"]])
    for target, libs in re.findall(r"^target_link_libraries\(lem_(\w+?)(?:_lib)? "
                                   r"(?:PUBLIC|PRIVATE) ([^)]*)\)", cmake_text, re.M):
        if target in modules:
            modules[target][1].extend(lib.split("::")[0] for lib in libs.split())
    return modules


def table_row(cells):
    """(module, headers, source folders, may use, external libraries, files
    the "owns" column names) of one row of the table."""
    module, files, may_use, owns = cells[0], cells[1], cells[2], cells[3]
    named = CODE.findall(files)
    headers = sorted(n for n in named if n.endswith(".hpp"))
    folders = [n for n in named if not n.endswith(".hpp")]
    uses, _, libs = may_use.partition("(")
    uses = [] if uses.strip() == "—" else [u.strip() for u in uses.split(",")]
    libs = [lib.strip() for lib in libs.rstrip(")").split(",") if lib.strip()]
    mentioned = [n for n in CODE.findall(owns) if re.fullmatch(r"[\w/]+\.[ch]pp", n)]
    return module, headers, folders, uses, libs, mentioned


def table_problems(rows, modules, root):
    """Where the table's rows (lists of cells) disagree with `modules`
    (declared_modules) and with the files under `root`."""
    problems = []
    named = [cells[0] for cells in rows if cells[0] not in NOT_MODULES]
    if named != list(modules):
        problems.append("the rows name the modules %s; the lem_module() lines, in order, %s"
                        % (named, list(modules)))
    for cells in rows:
        if cells[0] not in modules:
            continue
        module, headers, folders, uses, libs, mentioned = table_row(cells)
        include = os.path.join(root, "include", "lem", module)
        source = os.path.join(root, "src", module)
        actual = sorted(f for f in os.listdir(include) if f.endswith(".hpp"))
        for name in sorted(set(actual) - set(headers)):
            problems.append("%s: include/lem/%s/%s is missing from the row" % (module, module, name))
        for name in sorted(set(headers) - set(actual)):
            problems.append("%s: the row names the header %s, not in include/lem/%s/"
                            % (module, name, module))
        if folders != ["src/%s/" % module]:
            problems.append("%s: the row names %s for the sources, not src/%s/"
                            % (module, folders, module))
        depends, externals = modules[module]
        if uses != depends:
            problems.append("%s: the row may use %s; its lem_module() DEPENDS %s"
                            % (module, uses, depends))
        if sorted(libs) != sorted(externals):
            problems.append("%s: the row names the libraries %s; CMake links %s"
                            % (module, libs, externals))
        for name in mentioned:
            if not any(os.path.exists(os.path.join(folder, name)) for folder in (source, include)):
                problems.append("%s: the row names %s, which is not in src/%s/ or include/lem/%s/"
                                % (module, name, module, module))
    return problems


def test_module_table_matches_the_code():
    with open(os.path.join(ROOT, "CMakeLists.txt"), encoding="utf-8") as f:
        modules = declared_modules(f.read())
    assert modules, "no lem_module() line in CMakeLists.txt"
    problems = table_problems(markdown_table(PAGE, "module"), modules, ROOT)
    assert not problems, "\n".join(problems)


@pytest.mark.parametrize("folder", ["src", os.path.join("include", "lem")])
def test_every_folder_is_a_module(folder):
    with open(os.path.join(ROOT, "CMakeLists.txt"), encoding="utf-8") as f:
        modules = set(declared_modules(f.read()))
    path = os.path.join(ROOT, folder)
    folders = {d for d in os.listdir(path) if os.path.isdir(os.path.join(path, d))}
    assert folders == modules, "%s/ holds %s; the modules are %s" % (folder, sorted(folders),
                                                                     sorted(modules))


def test_table_rule_catches_a_wrong_row(tmp_path):
    """A row that drifted is named: a header missing, a dependency left over,
    a library left out, a file that is not there, a module missing."""
    for sub in ("include/lem/a", "include/lem/b", "src/a", "src/b"):
        os.makedirs(tmp_path / sub)
    for name in ("include/lem/a/one.hpp", "include/lem/b/two.hpp", "include/lem/b/three.hpp",
                 "src/b/three.cpp"):
        (tmp_path / name).write_text("")
    modules = declared_modules("lem_module(a LIBS MPI::MPI_CXX)\n"
                               "lem_module(b DEPENDS a)\n"
                               "target_link_libraries(lem_b PRIVATE METIS::METIS)\n")
    assert modules == {"a": ([], ["MPI"]), "b": (["a"], ["METIS"])}
    good = [["a", "`one.hpp`; `src/a/`", "— (MPI)", "ground"],
            ["b", "`two.hpp`, `three.hpp`; `src/b/`", "a (METIS)", "the thing (`three.cpp`)"],
            ["drivers", "`drivers/*.cpp`", "everything", "mains"]]
    assert table_problems(good, modules, str(tmp_path)) == []
    wrong = [["a", "`one.hpp`; `src/a/`", "—", "ground"],
             ["b", "`two.hpp`; `src/b/`", "a, c (METIS)", "the thing (`four.cpp`)"]]
    problems = "\n".join(table_problems(wrong, modules, str(tmp_path)))
    for part in ("a: the row names the libraries []; CMake links ['MPI']",
                 "b: include/lem/b/three.hpp is missing from the row",
                 "b: the row may use ['a', 'c']", "the row names four.cpp"):
        assert part in problems
    assert "the lem_module() lines" in "\n".join(table_problems(wrong[1:], modules,
                                                                 str(tmp_path)))
