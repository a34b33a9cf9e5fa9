"""Shared command-line options of the Python examples (not an example itself)."""

import argparse
from typing import Optional

import mcm


def parser(description: str) -> argparse.ArgumentParser:
    """The options every example takes, with the real robot's defaults."""
    p = argparse.ArgumentParser(description=description)
    p.add_argument("--host", default=mcm.DEFAULT_HOST, help="MCM address (default: the robot's, %(default)s)")
    p.add_argument("--port", type=int, default=mcm.DEFAULT_PORT, help="JSON port (default %(default)s)")
    p.add_argument("--instance", default="default", help="MCM instance, for shared memory (default %(default)s)")
    return p


def ready(client: mcm.Client, log: Optional[bool] = True) -> mcm.Status:
    """HOLD with every axis calibrated: `hold`, then `calibrate` if an axis is not."""
    client.hold()
    s = client.status(detail=True)
    assert s.detail is not None
    if not s.detail.all_calibrated:
        if log:
            print("calibrating (about 12 s on the simulated arm) ...", flush=True)
        client.calibrate()
    return client.hold()
