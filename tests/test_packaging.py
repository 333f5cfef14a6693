"""The distribution: an sdist and a wheel built from it carry everything the package serves,
and a wheel installed into a fresh virtual environment serves the viewer page and the
vendored three.js with no npm and no source checkout. The optional compiled tf2 kernels are
in the wheel where the build machine has a C compiler and are used once installed; a wheel
built where the compiler fails still builds, installs and answers lookups in pure Python.

Oracles: the files in the repository (byte comparison of what the installed server sends),
the wheel's file list, the installed package's location (outside the checkout), and a tf2
lookup in the installed package against closed-form values.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import tarfile
import time
import urllib.request
import venv
import zipfile
from pathlib import Path

import pytest

from _support.ports import free_port
from _support.procs import Proc

REPO = Path(__file__).resolve().parents[1]
WEB = REPO / "src" / "posekit" / "viewer" / "web"
#: The page, every script and style of the app (display modules included), and the parts of
#: three.js the page imports.
SERVED = ["index.html",
          *sorted(p.relative_to(WEB).as_posix() for p in (WEB / "app").rglob("*")
                  if p.suffix in (".js", ".css")),
          "vendor/three/build/three.module.js", "vendor/three/build/three.core.js",
          "vendor/three/examples/jsm/controls/OrbitControls.js", "vendor/three/LICENSE"]

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def dist(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """sdist, then a wheel built from that sdist (python -m build)."""
    pytest.importorskip("build", reason="the dev extra's 'build' is not installed")
    out = tmp_path_factory.mktemp("dist")
    subprocess.run([sys.executable, "-m", "build", "--outdir", str(out), str(REPO)],
                   check=True, capture_output=True, timeout=240)
    return out


def test_sdist_and_wheel_carry_the_served_files_licences_and_one_version(dist: Path) -> None:
    import posekit

    (wheel,) = dist.glob("posekit-*.whl")
    (sdist,) = dist.glob("posekit-*.tar.gz")
    assert wheel.name.startswith(f"posekit-{posekit.__version__}-")
    names = set(zipfile.ZipFile(wheel).namelist())
    # the optional extensions, built here because this machine has a C compiler
    for package in ("tf2", "geometry"):
        assert any(n.startswith(f"posekit/{package}/_accel.") and n.endswith((".so", ".pyd"))
                   for n in names), sorted(n for n in names if "_accel" in n)
    for rel in SERVED:
        assert f"posekit/viewer/web/{rel}" in names, rel
    assert not any("node_modules" in n for n in names)
    assert any(n.endswith("licenses/LICENSE") for n in names)
    with tarfile.open(sdist) as tar:
        members = {m.name.split("/", 1)[1] for m in tar.getmembers() if "/" in m.name}
    for rel in ("LICENSE", "CHANGELOG.md", "pyproject.toml", "setup.py",
                "src/posekit/tf2/_accel.c", "src/posekit/geometry/_accel.c",
                "examples/dynamic_detector_demo.py",
                *(f"src/posekit/viewer/web/{r}" for r in SERVED)):
        assert rel in members, rel


_LOOKUP = """
import math, sys
from posekit.msgs.geometry_msgs import TransformStamped
from posekit.tf2 import BufferCore, path
core = BufferCore()
for k in range(2):
    m = TransformStamped()
    m.header.frame_id, m.child_frame_id = "odom", "base"
    m.header.stamp.sec = 10 + k
    m.transform.translation.x = 2.0 * k
    m.transform.rotation.z, m.transform.rotation.w = math.sin(0.5 * k), math.cos(0.5 * k)
    core.set_transform(m, "test")
out = core.lookup_transform_core("odom", "base", 10_500_000_000).transform
print(path.accelerated, out.translation.x, round(out.rotation.z, 12), round(math.sin(0.25), 12))
"""


def _fresh_venv_with(wheel: Path, env_dir: Path) -> Path:
    """A new virtual environment with ``wheel`` installed (no index) and the dev venv's
    dependencies visible; returns its python."""
    venv.EnvBuilder(with_pip=True).create(env_dir)  # ensurepip: offline
    python = env_dir / "bin" / "python"
    site = Path(subprocess.run(
        [str(python), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
        check=True, capture_output=True, text=True).stdout.strip())
    subprocess.run([str(python), "-m", "pip", "install", "--quiet", "--no-deps",
                    "--no-index", "--disable-pip-version-check", str(wheel)],
                   check=True, capture_output=True, timeout=120)
    dev_site = next(p for p in sys.path if p.endswith("site-packages"))
    (site / "_dev_dependencies.pth").write_text(dev_site + "\n")
    return python


def _installed_lookup(python: Path, cwd: Path) -> list[str]:
    env = {k: v for k, v in os.environ.items() if not k.startswith(("POSEKIT_", "PYTHON"))}
    return subprocess.run([str(python), "-c", _LOOKUP], check=True, capture_output=True,
                          text=True, cwd=cwd, env=env, timeout=60).stdout.split()


def test_installed_wheel_uses_the_compiled_tf2_kernels(dist: Path, tmp_path: Path) -> None:
    (wheel,) = dist.glob("posekit-*.whl")
    python = _fresh_venv_with(wheel, tmp_path / "venv")
    accelerated, x, z, want_z = _installed_lookup(python, tmp_path)
    assert (accelerated, x, z) == ("True", "1.0", want_z)


def test_wheel_without_a_compiler_installs_pure_python(tmp_path: Path) -> None:
    """CC=false: the optional extension fails to build, the wheel is still made, and the
    installed package answers the same lookup in pure Python."""
    out = tmp_path / "wheel"
    env = {**os.environ, "CC": "false", "LDSHARED": "false"}
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--quiet", "--no-deps",
                    "--disable-pip-version-check", "-w", str(out), str(REPO)],
                   check=True, capture_output=True, timeout=240, env=env)
    (wheel,) = out.glob("posekit-*.whl")
    assert not [n for n in zipfile.ZipFile(wheel).namelist() if n.endswith((".so", ".pyd"))]
    python = _fresh_venv_with(wheel, tmp_path / "venv")
    accelerated, x, z, want_z = _installed_lookup(python, tmp_path)
    assert (accelerated, x, z) == ("False", "1.0", want_z)


def test_installed_wheel_serves_the_viewer_and_three_js(dist: Path, tmp_path: Path) -> None:
    (wheel,) = dist.glob("posekit-*.whl")
    env_dir = tmp_path / "venv"
    # The wheel alone is installed from the file (--no-deps --no-index: nothing fetched); its
    # dependencies come from the dev venv's site-packages, appended after the fresh venv's
    # own through a .pth path line (which does not run the dev venv's editable-install hook).
    python = _fresh_venv_with(wheel, env_dir)
    where = subprocess.run([str(python), "-c", "import posekit; print(posekit.__file__)"],
                           check=True, capture_output=True, text=True, cwd=tmp_path)
    assert Path(where.stdout.strip()).is_relative_to(env_dir), where.stdout
    port = free_port()
    env = {k: v for k, v in os.environ.items() if not k.startswith(("POSEKIT_", "PYTHON"))}
    proc = Proc([str(env_dir / "bin" / "posekit"), "view", "--scenario", "empty_world",
                 "--port", str(port)], env=env, cwd=tmp_path)
    try:
        base = f"http://127.0.0.1:{port}/"
        deadline = time.monotonic() + 30.0
        while _get(base) is None:
            assert proc.popen.poll() is None, f"posekit view exited\n{proc.describe()}"
            assert time.monotonic() < deadline, f"no viewer page after 30 s\n{proc.describe()}"
            time.sleep(0.1)
        for rel in SERVED:
            url = base if rel == "index.html" else base + rel
            if rel.startswith("vendor/"):
                url = base + "vendor/three/" + rel.removeprefix("vendor/three/")
            assert _get(url) == (WEB / rel).read_bytes(), rel
    finally:
        proc.kill(signal.SIGINT)
        proc.kill()


def _get(url: str) -> bytes | None:
    try:
        with urllib.request.urlopen(url, timeout=5) as response:
            return bytes(response.read())
    except OSError:
        return None
