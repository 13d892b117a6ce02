"""Command-line plumbing shared by the commands: argparse with the module's
docstring as help, and ToolError / OSError turned into one error line."""
import argparse
import sys

from .errors import ToolError


def parser(doc, **kwargs):
    """An ArgumentParser whose description is the first line of `doc` and whose
    epilog is the rest, both kept as written."""
    summary, _, details = doc.strip().partition("\n")
    return argparse.ArgumentParser(description=summary, epilog=details.strip() or None,
                                   formatter_class=argparse.RawDescriptionHelpFormatter,
                                   **kwargs)


def run(arg_parser, work, argv=None):
    """Parse argv, call work(args) and return its exit status (0 for None);
    a ToolError or OSError becomes `PROG: error: MESSAGE` and status 1."""
    args = arg_parser.parse_args(argv)
    try:
        return work(args) or 0
    except (ToolError, OSError) as e:
        sys.stderr.write("%s: error: %s\n" % (arg_parser.prog, e))
        return 1


def run_on_folder(doc, folder_help, work, argv=None):
    """The usual command: one RESULTS_DIR argument, work(RESULTS_DIR)."""
    arg_parser = parser(doc)
    arg_parser.add_argument("results_dir", metavar="RESULTS_DIR", help=folder_help)
    return run(arg_parser, lambda args: work(args.results_dir), argv)
