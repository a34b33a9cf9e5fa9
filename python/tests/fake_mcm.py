"""A scripted stand-in for the MCM's JSON port, for the unit tests: it answers each command
line with what ``handler(command)`` returns (a list of result lines, possibly empty)."""

import json
import socket
import threading
from typing import Any, Callable, Dict, List


class FakeMcm:
    def __init__(self, handler: Callable[[Dict[str, Any]], List[Any]]) -> None:
        self.handler = handler
        self.received: List[Dict[str, Any]] = []
        self.connections = 0
        self._srv = socket.socket()
        self._srv.bind(("127.0.0.1", 0))
        self._srv.listen(4)
        self.port = self._srv.getsockname()[1]
        self._conns: List[socket.socket] = []
        threading.Thread(target=self._accept, daemon=True).start()

    def _accept(self) -> None:
        while True:
            try:
                conn, _ = self._srv.accept()
            except OSError:
                return
            self.connections += 1
            self._conns.append(conn)
            threading.Thread(target=self._serve, args=(conn,), daemon=True).start()

    def _serve(self, conn: socket.socket) -> None:
        buf = b""
        while True:
            try:
                data = conn.recv(65536)
            except OSError:
                return
            if not data:
                return
            buf += data
            while b"\n" in buf:
                line, buf = buf.split(b"\n", 1)
                cmd = json.loads(line)
                self.received.append(cmd)
                for out in self.handler(cmd):
                    if out == "CLOSE":
                        conn.close()
                        return
                    text = out if isinstance(out, str) else json.dumps(out)
                    conn.sendall(text.encode("ascii") + b"\n")

    def drop_connections(self) -> None:
        for c in self._conns:
            try:
                c.shutdown(socket.SHUT_RDWR)
                c.close()
            except OSError:
                pass

    def close(self) -> None:
        self.drop_connections()
        self._srv.close()


OK = {"result_type": "generic", "error_status": "OK"}


def status(mode: str = "HOLD", t: float = 1.0, pos0: float = 0.0) -> Dict[str, Any]:
    six = [0.0] * 6
    return {
        "result_type": "status",
        "operating_mode": mode,
        "axis_states": {"time": [t] * 6, "position": [pos0] + [0.0] * 5, "velocity": six,
                        "acceleration": six, "current": six},
    }


def error(message: str, **extra: Any) -> Dict[str, Any]:
    v = {"result_type": "generic", "error_status": "ERROR", "error_message": message}
    v.update(extra)
    return v
