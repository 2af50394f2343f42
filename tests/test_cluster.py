"""Batches on a Dask cluster (vecmsaa.tools.cluster): a real distributed.LocalCluster with two
worker processes, no mocks. The truth is the local batch: outputs must be equal byte for byte,
failures must be the same lines."""
from __future__ import annotations

import os
import shutil
import sys

import numpy as np
import pytest

distributed = pytest.importorskip("distributed")

from PIL import Image  # noqa: E402

from vecmsaa.cli.main import main as vecmsaa_main  # noqa: E402
from vecmsaa.output.png import encode_png  # noqa: E402
from vecmsaa.api import render_svg_array  # noqa: E402
from vecmsaa.tools import cluster as cluster_mod  # noqa: E402


@pytest.fixture(scope="module")
def scheduler():
    """The address of a local cluster of two single-threaded worker processes. A task whose
    worker dies is not retried, so a crashing file fails at once."""
    import dask

    with dask.config.set({"distributed.scheduler.allowed-failures": 0}), \
            distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                     dashboard_address=None) as local:
        yield local.scheduler_address


def cli(capsys, *argv):
    try:
        status = vecmsaa_main([str(a) for a in argv])
    except SystemExit as exc:
        status = exc.code
    out, err = capsys.readouterr()
    return status, out, err


def make_tree(root):
    """Drawings whose images sit beside them, below them and in a resources folder, plus a
    broken file."""
    svgs, resources = root / "svgs", root / "res"
    (svgs / "sub").mkdir(parents=True)
    resources.mkdir()
    pixels = np.zeros((8, 8, 4), np.uint8)
    pixels[..., 0], pixels[..., 3] = 200, 255
    pixels[2:5, 2:6, 1] = 180
    Image.fromarray(pixels).save(svgs / "sub" / "pic.png")
    Image.fromarray(pixels[::-1, ::-1].copy()).save(resources / "other.png")
    (svgs / "images.svg").write_text(
        '<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" '
        'width="40" height="30"><image x="2" y="2" width="16" height="16" '
        'xlink:href="sub/pic.png"/><image x="20" y="2" width="16" height="16" '
        "href='other.png'/><circle cx=\"20\" cy=\"22\" r=\"6.3\" fill=\"teal\"/></svg>")
    for i in range(3):
        (svgs / f"shape{i}.svg").write_text(
            '<svg xmlns="http://www.w3.org/2000/svg" width="40" height="30">'
            f'<rect x="{3.3 + i}" y="4.1" width="20" height="10" fill="#c03020"/>'
            f'<path d="M2 28 L38 {3 + i} L38 8 Z" fill="#2040c0" fill-opacity="0.7"/></svg>')
    (svgs / "broken.svg").write_text("<svg")
    return svgs, resources


def test_render_batch_equals_the_local_batch(tmp_path, capsys, scheduler):
    svgs, resources = make_tree(tmp_path)
    local = cli(capsys, "render", svgs, "--out-dir", tmp_path / "local", "--resources-dir",
                resources)
    remote = cli(capsys, "render", svgs, "--out-dir", tmp_path / "remote", "--resources-dir",
                 resources, "--scheduler", scheduler)
    assert local[0] == remote[0] == 1                      # broken.svg fails, alone
    assert local[2] == remote[2]                           # the same progress and failure lines
    assert "FAILED" in remote[2] and "broken.svg: malformed XML" in remote[2]
    names = sorted(p.name for p in (tmp_path / "local").iterdir())
    assert names == ["images.png", "shape0.png", "shape1.png", "shape2.png"]
    assert sorted(p.name for p in (tmp_path / "remote").iterdir()) == names
    for name in names:
        assert (tmp_path / "local" / name).read_bytes() == \
            (tmp_path / "remote" / name).read_bytes(), name
    # The images did render (a missing file would leave them out): red and green pixels.
    picture = np.asarray(Image.open(tmp_path / "remote" / "images.png"))
    assert tuple(picture[8, 8][:3]) == (200, 180, 0) and tuple(picture[4, 22][:3]) == (200, 0, 0)


def test_workers_need_only_the_bundle(tmp_path, scheduler):
    """What goes to a worker is the bundle: with the drawing's folders deleted on this side,
    the worker still renders the same bytes."""
    svgs, resources = make_tree(tmp_path)
    svg = svgs / "images.svg"
    expected = encode_png(render_svg_array(svg, resources_dir=resources))
    bundle = cluster_mod.bundle_svg(svg, resources)
    assert sorted(bundle.files) == ["res/other.png", "svgs/images.svg", "svgs/sub/pic.png"]
    assert not any(os.path.isabs(p) or ".." in p.split("/") for p in bundle.files)
    shutil.rmtree(svgs)
    shutil.rmtree(resources)
    with distributed.Client(scheduler, set_as_default=False) as client:
        png = client.submit(cluster_mod.render_bundle, render_svg_array, bundle, None,
                            {"mode": "approx"}, pure=False).result()
    assert png == expected


def test_golden_update_and_check_on_the_cluster(tmp_path, capsys, scheduler):
    svgs, resources = make_tree(tmp_path)
    (svgs / "broken.svg").unlink()
    here, there = tmp_path / "g-local", tmp_path / "g-cluster"
    assert cli(capsys, "golden", "update", svgs, "--goldens", here, "--resources-dir",
               resources, "--samples", 16)[0] == 0
    assert cli(capsys, "golden", "update", svgs, "--goldens", there, "--resources-dir",
               resources, "--samples", 16, "--scheduler", scheduler)[0] == 0
    files = sorted(p.relative_to(here) for p in here.rglob("*") if p.is_file())
    assert len(files) == 5    # four goldens and the manifest
    for rel in files:
        assert (here / rel).read_bytes() == (there / rel).read_bytes(), rel
    (svgs / "shape1.svg").write_text((svgs / "shape1.svg").read_text().replace("#c03020",
                                                                                "#c03030"))
    local = cli(capsys, "golden", "check", svgs, "--goldens", here)
    remote = cli(capsys, "golden", "check", svgs, "--goldens", there, "--scheduler", scheduler)
    assert local[0] == remote[0] == 1
    assert local[1].replace(str(here), "G") == remote[1].replace(str(there), "G")
    assert "FAIL" in remote[1] and "shape1.svg" in remote[1]


def _dies_on_crash_svg(source, **options):
    if os.path.basename(source) == "crash.svg":
        os._exit(3)   # the worker process dies, as on a segmentation fault or an OOM kill
    return render_svg_array(source, **options)


def test_a_file_whose_worker_dies_fails_alone(tmp_path, scheduler):
    import cloudpickle

    from vecmsaa.tools import golden

    svgs, _ = make_tree(tmp_path)
    (svgs / "broken.svg").unlink()
    (svgs / "crash.svg").write_text((svgs / "shape0.svg").read_text())
    cloudpickle.register_pickle_by_value(sys.modules[__name__])  # workers cannot import tests
    try:
        result = golden.update_goldens(svgs, tmp_path / "g", golden.render_options(),
                                       render=_dies_on_crash_svg, scheduler=scheduler)
    finally:
        cloudpickle.unregister_pickle_by_value(sys.modules[__name__])
    assert [str(svg) for svg, _ in result.errors] == ["crash.svg"]
    assert "worker rendering it died" in result.errors[0][1]
    assert len(result.written) == 4


def test_suite_on_the_cluster_gives_the_local_results(shared_dir, scheduler):
    from vecmsaa.tools.suite import _reference, collect, judge, render_test, run_suite, \
        suite_options

    suite = shared_dir / "resvg-suite"
    names = collect(suite / "tests", only=["structure/image/external-png",
                                           "structure/image/external-svg-with-transform",
                                           "text/text/dx-and-dy-instead-of-x-and-y"])
    assert len(names) == 3
    # The local truth without run_one's time limit, which a loaded machine can exceed.
    local = {}
    for name in names:
        ref = _reference(str(suite), name)
        actual = render_test(str(suite / "tests" / f"{name}.svg"), ref.shape[1], ref.shape[0],
                             **suite_options(str(suite)))
        local[name] = judge(name, actual, ref, None, str(suite))[1]
    remote = run_suite(str(suite), names, scheduler=scheduler)
    assert remote == local


def test_unreachable_scheduler_is_a_clear_error(capsys):
    import socket

    with socket.socket() as s:   # a port nothing listens on
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    with pytest.raises(cluster_mod.ClusterError, match="cannot reach the Dask scheduler"):
        cluster_mod.Cluster(f"tcp://127.0.0.1:{port}", timeout=1)
