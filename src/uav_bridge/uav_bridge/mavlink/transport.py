"""Byte transports of a MAVLink link: TCP client, UDP listening or sending (no rclpy).

URLs follow pymavlink's: ``tcp:HOST:PORT`` connects to an autopilot serving TCP (ArduPilot
SITL serves 5760); ``udpin:HOST:PORT`` (or ``udp:HOST:PORT``) listens and answers whoever
sent the last datagram; ``udpout:HOST:PORT`` sends to that address and reads the replies on
the same socket. All sockets are non-blocking: :meth:`Transport.recv` returns what has
arrived (possibly nothing) and never waits, so the link's thread polls with ``select``.
"""

from __future__ import annotations

import select
import socket
import time
from dataclasses import dataclass

KINDS = ('tcp', 'udpin', 'udpout')


class LinkClosed(Exception):
    """The other side closed the connection, or the socket failed."""


@dataclass(frozen=True)
class Endpoint:
    """A parsed link URL."""

    kind: str
    host: str
    port: int

    def __str__(self) -> str:
        return f'{self.kind}:{self.host}:{self.port}'


def parse_url(url: str) -> Endpoint:
    """Parse ``tcp:HOST:PORT``, ``udp:``/``udpin:HOST:PORT`` or ``udpout:HOST:PORT``.

    Raises ValueError naming what is wrong with ``url``.
    """
    parts = url.split(':')
    if len(parts) != 3:
        raise ValueError(f'link URL {url!r}: expected KIND:HOST:PORT with KIND one of tcp, udp, udpin, udpout')
    kind, host, port_text = parts
    kind = 'udpin' if kind == 'udp' else kind
    if kind not in KINDS:
        raise ValueError(f'link URL {url!r}: unknown kind {parts[0]!r}, expected tcp, udp, udpin or udpout')
    if not host:
        raise ValueError(f'link URL {url!r}: empty host')
    try:
        port = int(port_text)
    except ValueError:
        raise ValueError(f'link URL {url!r}: port {port_text!r} is not a number') from None
    if not 0 < port < 65536:
        raise ValueError(f'link URL {url!r}: port {port} outside 1-65535')
    return Endpoint(kind, host, port)


class Transport:
    """One open socket of a link; :meth:`open` raises OSError when it cannot be opened."""

    def __init__(self, endpoint: Endpoint) -> None:
        self.endpoint = endpoint
        self._socket: socket.socket | None = None
        self._peer: tuple[str, int] | None = None

    @classmethod
    def open(cls, endpoint: Endpoint, connect_timeout: float = 1.0) -> Transport:
        """Open the socket of ``endpoint`` (a TCP connect waits up to ``connect_timeout`` s)."""
        transport = cls(endpoint)
        address = (endpoint.host, endpoint.port)
        if endpoint.kind == 'tcp':
            sock = socket.create_connection(address, timeout=connect_timeout)
            sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        else:
            sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
            if endpoint.kind == 'udpin':
                sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
                try:
                    sock.bind(address)
                except OSError:
                    sock.close()
                    raise
            else:
                transport._peer = address
        sock.setblocking(False)
        transport._socket = sock
        return transport

    def wait_readable(self, timeout: float) -> bool:
        """Wait up to ``timeout`` s for bytes to read; True when there are some."""
        if self._socket is None:
            return False
        readable, _, _ = select.select([self._socket], [], [], max(0.0, timeout))
        return bool(readable)

    def recv(self) -> bytes:
        """Return the bytes that have arrived (``b''`` when none); LinkClosed on EOF or error."""
        if self._socket is None:
            raise LinkClosed('link is closed')
        chunks = []
        while True:
            try:
                if self.endpoint.kind == 'tcp':
                    data = self._socket.recv(65536)
                    if not data:
                        raise LinkClosed(f'{self.endpoint}: connection closed by the autopilot')
                else:
                    data, sender = self._socket.recvfrom(65536)
                    if self.endpoint.kind == 'udpin':
                        self._peer = sender
            except (BlockingIOError, InterruptedError):
                break
            except ConnectionRefusedError:
                if self.endpoint.kind == 'tcp':
                    raise LinkClosed(f'{self.endpoint}: connection refused') from None
                break
            except OSError as error:
                raise LinkClosed(f'{self.endpoint}: {error.strerror or error}') from None
            chunks.append(data)
        return b''.join(chunks)

    def send(self, data: bytes) -> None:
        """Send ``data``; LinkClosed when the socket failed (a UDP peer not yet known drops it)."""
        if self._socket is None:
            raise LinkClosed('link is closed')
        try:
            if self.endpoint.kind == 'tcp':
                self._send_stream(data)
            elif self._peer is not None:
                self._socket.sendto(data, self._peer)
        except (BlockingIOError, InterruptedError):
            return
        except ConnectionRefusedError:
            if self.endpoint.kind == 'tcp':
                raise LinkClosed(f'{self.endpoint}: connection refused') from None
        except OSError as error:
            raise LinkClosed(f'{self.endpoint}: {error.strerror or error}') from None

    def _send_stream(self, data: bytes, timeout: float = 1.0) -> None:
        view = memoryview(data)
        deadline = time.monotonic() + timeout
        while view:
            try:
                view = view[self._socket.send(view):]
            except (BlockingIOError, InterruptedError):
                _, writable, _ = select.select([], [self._socket], [], max(0.0, deadline - time.monotonic()))
                if not writable:
                    raise LinkClosed(f'{self.endpoint}: sending blocked for {timeout:g} s') from None

    def close(self) -> None:
        """Close the socket (idempotent)."""
        if self._socket is not None:
            self._socket.close()
            self._socket = None
