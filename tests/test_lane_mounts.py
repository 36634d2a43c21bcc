"""The test lanes in the Debian 13 root (scripts/lane_root.sh): the /proc and /sys they mount for a command are
there for the command and gone after it, whether it failed or was killed."""
import os
import signal
import subprocess
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DEB13 = Path(os.environ.get("DEB13") or Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
             / "fenics_contact" / "debian13")

pytestmark = [
    pytest.mark.skipif(os.geteuid() != 0, reason="the lanes need root (chroot, mount)"),
    pytest.mark.skipif(not (DEB13 / "bin" / "sh").exists(), reason=f"no Debian 13 root at {DEB13}"),
    pytest.mark.skipif(subprocess.run(["sh", "-c", "command -v unshare"], capture_output=True).returncode != 0,
                       reason="no unshare (util-linux)"),
]


def mounted_under(root: Path) -> list[str]:
    """Mount points of this mount namespace at or below ``root``."""
    prefix = str(root.resolve())
    points = [line.split()[1] for line in Path("/proc/mounts").read_text().splitlines()]
    return [p for p in points if p == prefix or p.startswith(prefix + "/")]


def lane_command(cmd: str) -> subprocess.Popen:
    """``cmd`` run in the root as the lanes run their commands, in a process group of its own."""
    env = {**os.environ, "DEB13": str(DEB13), "LANE": "test"}
    return subprocess.Popen(["bash", "-c", '. scripts/lane_root.sh && lane_mounted "$0" /', cmd], cwd=ROOT, env=env,
                            start_new_session=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def test_a_failed_lane_command_had_proc_and_sys_and_leaves_nothing_mounted():
    assert mounted_under(DEB13) == []
    # exit status 3 only if /proc and /sys were there for the command
    assert lane_command("test -r /proc/self/status && test -d /sys/devices && exit 3").wait(60) == 3
    assert mounted_under(DEB13) == []


def test_a_killed_lane_command_leaves_nothing_mounted():
    marker = DEB13 / "tmp" / f"lane-mounts-test-{os.getpid()}"
    marker.unlink(missing_ok=True)
    p = lane_command(f"test -r /proc/self/status && touch /tmp/{marker.name} && sleep 60")
    try:
        for _ in range(300):
            if marker.exists() or p.poll() is not None:
                break
            time.sleep(0.1)
        assert marker.exists(), "the command did not start with /proc mounted"
    finally:
        os.killpg(p.pid, signal.SIGKILL)
        p.wait(60)
        marker.unlink(missing_ok=True)
    assert mounted_under(DEB13) == []
