"""Shared fixtures: a small job (a 2.56 mm, 64 x 64 patch of the paper-like surface)."""

from __future__ import annotations

import pytest

from asperity.pipelines.config import config_from_dict
from asperity.pipelines.job import run_job
from asperity.pipelines.report import write_report
from tests._helpers import small_data


def small_config(base_dir, **loading):
    """The validated small job configuration."""
    return config_from_dict(small_data(**loading), source="small", base_dir=base_dir)


@pytest.fixture
def small():
    """``small(base_dir, **loading)``: the small job's configuration (edit with ``data=``)."""

    def make(base_dir, data=None, **loading):
        data = small_data(**loading) if data is None else data
        return config_from_dict(data, source="small", base_dir=base_dir)

    make.data = small_data
    return make


@pytest.fixture(scope="session")
def small_run(tmp_path_factory):
    """The small job run once, with its report: (config, out_dir, JobResult)."""
    out = tmp_path_factory.mktemp("job")
    cfg = small_config(out)
    result = run_job(cfg, out)
    write_report(result, out)
    return cfg, out, result
