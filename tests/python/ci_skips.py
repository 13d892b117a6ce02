"""A pytest plugin (conftest.py loads it): under CI=true a skipped test, or a
module skipped at collection, is reported as a failure.  CI has every
package, so a skip there is a test that proved nothing; jobs/check-no-skips.sh
holds ctest to the same rule."""
import os

import pytest


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    outcome = yield
    report = outcome.get_result()
    if os.environ.get("CI") == "true" and report.skipped and not hasattr(report, "wasxfail"):
        reason = report.longrepr[2] if isinstance(report.longrepr, tuple) else report.longrepr
        report.outcome = "failed"
        report.longrepr = "CI=true: skipped tests count as failures (%s)" % reason


@pytest.hookimpl(hookwrapper=True)
def pytest_make_collect_report(collector):
    outcome = yield
    report = outcome.get_result()
    if os.environ.get("CI") == "true" and report.skipped:
        report.outcome = "failed"
        report.longrepr = "CI=true: a module skipped at collection counts as a failure"
