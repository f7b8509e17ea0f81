"""macOS and Windows (students use them, through pip or conda): the Linux-only parts step aside.

What a headless run reaches that is Linux-only: the free-memory estimate (/proc/meminfo, cgroups),
the GPU probe (/dev/dri), the Vulkan and display checks (libvulkan.so.1, DISPLAY), and the worker
pinning (sched_setaffinity, /proc/self/task; rigid/engine/threads.py returns when os has no
sched_getaffinity). Here each is asked as it would be on another platform."""
import os
import signal
import sys

import pytest


def test_gpu_candidates_include_metal_on_a_mac_only(monkeypatch):
    from rigid.runtime import gpu_candidates

    monkeypatch.setattr(sys, "platform", "linux")
    assert gpu_candidates() == ["cuda", "vulkan"]
    monkeypatch.setattr(sys, "platform", "darwin")
    assert gpu_candidates() == ["cuda", "metal", "vulkan"]


@pytest.mark.parametrize("platform", ["darwin", "win32"])
def test_vulkan_and_display_checks_leave_it_to_taichi_elsewhere(monkeypatch, platform):
    from rigid.view.vulkan import require_display, vulkan_problem

    monkeypatch.setattr(sys, "platform", platform)
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    assert vulkan_problem() is None
    require_display()  # no xvfb-run hint off Linux


def test_free_memory_without_proc_or_cgroups(monkeypatch):
    """No /proc/meminfo and no cgroup files (macOS, Windows): sysconf where it has the figure,
    else None, and the memory check then lets the scene through rather than failing."""
    from pathlib import Path

    from rigid.bodies import budget

    real = Path.read_text

    def no_linux_files(self, *args, **kwargs):
        if str(self).startswith(("/proc", "/sys")):
            raise FileNotFoundError(self)
        return real(self, *args, **kwargs)

    monkeypatch.setattr(Path, "read_text", no_linux_files)
    free = budget.available_bytes()
    assert free is None or free > 0
    monkeypatch.setattr(os, "sysconf", lambda name: (_ for _ in ()).throw(ValueError(name)))
    assert budget.available_bytes() is None
    budget.check_fits(1e15, "a huge scene", "use less")  # cannot tell: not refused


def test_ctrl_c_stops_at_once_inside_and_is_given_back_after():
    """SIGINT's default action (on every platform) while the kernels compile, then the handler from
    before; a Ctrl-C ignored on purpose (nohup) stays ignored."""
    from rigid.run.compile_guard import ctrl_c_stops_at_once

    def mine(signum, frame):
        pass

    previous = signal.signal(signal.SIGINT, mine)
    try:
        with ctrl_c_stops_at_once():
            assert signal.getsignal(signal.SIGINT) is signal.SIG_DFL
        assert signal.getsignal(signal.SIGINT) is mine
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        with ctrl_c_stops_at_once():
            assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN
    finally:
        signal.signal(signal.SIGINT, previous)
