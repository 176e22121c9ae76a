"""The middleware's sleeps (src/sleep.cpp) with bad arguments and outside a capture's warp, through
the C library's names (ctypes finds the preloaded definitions first): before rclpy.init (no
session) and after it (a session, before any warp), each call behaves as the C library's does.
Prints one JSON object of what it saw."""
import ctypes
import json
import time

import rclpy
from std_msgs.msg import String


class Timespec(ctypes.Structure):
    _fields_ = [("tv_sec", ctypes.c_long), ("tv_nsec", ctypes.c_long)]


libc = ctypes.CDLL(None, use_errno=True)
CLOCK_MONOTONIC, CLOCK_BOOTTIME, TIMER_ABSTIME = 1, 7, 1


def probe():
    seen = {}
    ctypes.set_errno(0)
    seen["nanosleep_null"] = (libc.nanosleep(None, None), ctypes.get_errno())
    ctypes.set_errno(0)
    seen["nanosleep_bad_nsec"] = (libc.nanosleep(ctypes.byref(Timespec(0, 2_000_000_000)), None),
                                  ctypes.get_errno())
    ctypes.set_errno(0)
    seen["nanosleep_negative"] = (libc.nanosleep(ctypes.byref(Timespec(-1, 0)), None), ctypes.get_errno())
    seen["clock_nanosleep_bad_clock"] = libc.clock_nanosleep(12345, 0, ctypes.byref(Timespec(0, 1000)), None)
    seen["clock_nanosleep_null"] = libc.clock_nanosleep(CLOCK_MONOTONIC, 0, None, None)
    # An absolute deadline in the past ends at once; another clock sleeps for real.
    seen["clock_nanosleep_past"] = libc.clock_nanosleep(
        CLOCK_MONOTONIC, TIMER_ABSTIME, ctypes.byref(Timespec(1, 0)), None)
    t = time.monotonic()
    seen["clock_nanosleep_boottime"] = libc.clock_nanosleep(
        CLOCK_BOOTTIME, 0, ctypes.byref(Timespec(0, 50_000_000)), None)
    seen["boottime_slept"] = time.monotonic() - t
    t = time.monotonic()
    seen["usleep"] = libc.usleep(50_000)
    seen["usleep_slept"] = time.monotonic() - t
    seen["sleep_zero"] = libc.sleep(0)
    t = time.monotonic()
    time.sleep(0.05)
    seen["time_sleep_slept"] = time.monotonic() - t
    return seen


def main():
    before = probe()
    rclpy.init()
    node = rclpy.create_node("sleep_arguments")
    node.create_publisher(String, "args", 10)  # a session, and no activity: no warp comes
    after = probe()
    print(json.dumps({"before": before, "after": after}), flush=True)
    node.destroy_node()
    rclpy.shutdown()


if __name__ == "__main__":
    main()
