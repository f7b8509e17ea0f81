"""Is there a Vulkan device for GGUI? Asked before Taichi tries, so the answer is one line.

Taichi's GGUI (the window; recordings draw with raster.py and need no Vulkan) needs Vulkan. Without it,
Taichi prints a C++ "RHI Error" and raises; a window without a display even
ends the process from C++. So we ask the Vulkan loader ourselves (ctypes,
no extra package): create an instance, count the physical devices. On a
machine without a GPU, Mesa's lavapipe (package mesa-vulkan-drivers) is a
software Vulkan device that is enough for GGUI.
"""
from __future__ import annotations

import ctypes
import os
import sys

from ..errors import UserError

INSTALL_HINT = ("install Mesa's software Vulkan: sudo apt-get install mesa-vulkan-drivers "
                "(or run scripts/setup.sh)")
_VK_SUCCESS = 0
_VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO = 1


class _InstanceCreateInfo(ctypes.Structure):
    _fields_ = [("sType", ctypes.c_int), ("pNext", ctypes.c_void_p), ("flags", ctypes.c_uint32),
                ("pApplicationInfo", ctypes.c_void_p), ("enabledLayerCount", ctypes.c_uint32),
                ("ppEnabledLayerNames", ctypes.c_void_p), ("enabledExtensionCount", ctypes.c_uint32),
                ("ppEnabledExtensionNames", ctypes.c_void_p)]


def vulkan_problem() -> str | None:
    """None if a Vulkan device is there (or we cannot tell: not Linux), else what is missing."""
    if not sys.platform.startswith("linux"):
        return None  # macOS (MoltenVK inside Taichi) and Windows: let Taichi decide
    try:
        vk = ctypes.CDLL("libvulkan.so.1")
    except OSError:
        return "no Vulkan loader (libvulkan.so.1)"
    instance = ctypes.c_void_p()
    info = _InstanceCreateInfo(sType=_VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO)
    if vk.vkCreateInstance(ctypes.byref(info), None, ctypes.byref(instance)) != _VK_SUCCESS:
        return "no Vulkan driver (the Vulkan loader found no installable driver)"
    try:
        count = ctypes.c_uint32(0)
        result = vk.vkEnumeratePhysicalDevices(instance, ctypes.byref(count), None)
        if result != _VK_SUCCESS or count.value == 0:
            return "no Vulkan device (the Vulkan driver sees no GPU, and no software device)"
    finally:
        vk.vkDestroyInstance(instance, None)
    return None


def require_vulkan(purpose: str) -> None:
    """Raise a one-line UserError naming the missing piece and the install command."""
    problem = vulkan_problem()
    if problem:
        raise UserError(f"{purpose} needs Vulkan: {problem}; {INSTALL_HINT}")


def require_display() -> None:
    """A window needs a display; without one GLFW would end the process from C++."""
    if sys.platform.startswith("linux") and not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
        raise UserError("the window needs a display and none is set (DISPLAY); use --record out.mp4 or "
                        "--headless, or run under a virtual display: xvfb-run -a python rigid_body_dynamic.py")
