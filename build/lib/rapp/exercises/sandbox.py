"""Run a reader's object in a child process that cannot touch the judge.

A :class:`Sandbox` holds the reader's objects in a child process: its own process group
(killed whole), CPU-time and memory limits, a wall-clock deadline, and on Linux x86-64 a
seccomp filter that refuses the system calls that reach other processes (``kill``,
``ptrace``, ``setsid``...). The parent asks the child for *plain data* only: the answer
converted to numbers, lists, tuples, strings (:meth:`Sandbox.plain`), or what the reader's
function returns on given arguments (:meth:`Sandbox.call`). Replies travel as bounded JSON and
are rebuilt in the parent as fresh builtins and numpy arrays, so whatever the child does (patch
numpy, read the judge's frames, forge a report, exit) it can only change the data it sends,
never the code that judges it. Arguments travel the other way as pickles of the parent's own
values: every call gets its own copy.

The judges in :mod:`rapp.exercises.core` see a reader's function as a :class:`Remote`:
calling it runs the function in the child and returns plain data, or raises
:class:`SandboxError` (:class:`Raised`, :class:`TimedOut`, :class:`Died`).

Examples
--------
>>> with Sandbox.of({"f": lambda x: [x, (x, 2.5)]}, Limits(wall=5)) as box:
...     box.call("f", (1,))
[1, (1, 2.5)]
>>> with Sandbox.of({"x": 3}, Limits(wall=5)) as box:
...     box.plain("x")
3
"""

from __future__ import annotations

import ctypes
import io
import json
import math
import os
import pickle
import platform
import select
import signal
import struct
import sys
import time
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["Limits", "Sandbox", "Remote", "Opaque", "SandboxError", "Raised", "TimedOut", "Died",
           "MAX_MESSAGE", "bounded", "to_plain", "from_plain", "confine", "serve", "send_message"]

MAX_MESSAGE = 2000
"""Characters: the longest message a verdict carries (an exception's text is cut to fit)."""

MAX_REPLY = 16 * 2**20
"""Bytes: the largest reply a child may send; more is refused as 'too much data'."""


def bounded(text: Any, limit: int = MAX_MESSAGE) -> str:
    """``text`` as a string of at most ``limit`` characters.

    Examples
    --------
    >>> len(bounded("x" * 10**6)), bounded("short")
    (2000, 'short')
    """
    text = text if isinstance(text, str) else str(text)
    return text if len(text) <= limit else text[: limit - 3] + "..."


class SandboxError(Exception):
    """The reader's object did not give an answer: it raised, ran out of time, or died."""


class Raised(SandboxError):
    """The reader's code raised; ``str(err)`` is ``"TypeName: message"`` (bounded)."""


class TimedOut(SandboxError):
    """The reader's code did not finish within the wall-clock or CPU limit."""


class Died(SandboxError):
    """The child ended (exit, signal, memory limit) or sent something that is not a reply."""


@dataclass(frozen=True)
class Limits:
    """What a child may use.

    Attributes
    ----------
    wall : float
        Seconds of wall-clock time for the whole life of the child.
    cpu : float or None
        Seconds of CPU time (default: ``wall`` + 1).
    memory : int
        Bytes of address space the child may add to what it starts with.
    """

    wall: float = 5.0
    cpu: float | None = None
    memory: int = 1 << 30


@dataclass(frozen=True)
class Opaque:
    """An object the child could not turn into plain data: only its type name and repr."""

    type_name: str
    text: str

    def __repr__(self) -> str:
        return self.text


# --- plain data: what may cross from the child to the parent ---------------------------------

_ND_KINDS = "biuf"
_MAX_DEPTH = 20


def to_plain(value: Any, depth: int = 0) -> Any:
    """A JSON-able, tagged rendering of ``value`` (run in the child, on the reader's object).

    Numbers, strings, None, lists, tuples, dicts, numpy scalars and numeric arrays keep their
    type; rapp's obstacles and arms are sent as their constructor arguments; an object with
    ``__array__`` or ``__float__`` is converted as numpy would; anything else is opaque.
    """
    if depth > _MAX_DEPTH:
        return {"$": "opaque", "type": type(value).__name__, "repr": "<nested too deeply>"}
    t = type(value)
    if value is None or t is bool or t is str:
        return value if t is not str else bounded(value, 100_000)
    if t is int:
        return value if abs(value) < 2**63 else {"$": "float", "v": _float_text(float(value))}
    if t is float:
        return {"$": "float", "v": _float_text(value)}
    if isinstance(value, np.generic) and value.dtype.kind in _ND_KINDS:
        return {"$": "npscalar", "dtype": value.dtype.str, "v": _nd_items(np.asarray(value))}
    if isinstance(value, np.ndarray):
        if value.dtype.kind in _ND_KINDS:
            return {"$": "nd", "dtype": value.dtype.str, "shape": list(value.shape), "v": _nd_items(value)}
        return {"$": "ndobj", "shape": list(value.shape),
                "v": [to_plain(v, depth + 1) for v in value.ravel().tolist()]}
    if isinstance(value, bool):
        return bool(value)
    if isinstance(value, int):
        return to_plain(int(value), depth)
    if isinstance(value, float):
        return to_plain(float(value), depth)
    if isinstance(value, str):
        return bounded(str(value), 100_000)
    if isinstance(value, tuple):
        return {"$": "tuple", "v": [to_plain(v, depth + 1) for v in value]}
    if isinstance(value, list):
        return [to_plain(v, depth + 1) for v in value]
    if isinstance(value, dict):
        return {"$": "dict", "v": [[to_plain(k, depth + 1), to_plain(v, depth + 1)] for k, v in value.items()]}
    name = t.__name__
    if t.__module__ == "rapp.scenario" and name == "Scenario":
        return {"$": "rapp", "type": "Scenario", "v": [to_plain(value.to_dict(), depth + 1)]}
    if t.__module__.startswith("rapp.") and name in ("Circle", "Polygon", "Arm"):
        fields = {"Circle": ("center", "radius"), "Polygon": ("vertices",),
                  "Arm": ("link_lengths", "joint_limits")}[name]
        return {"$": "rapp", "type": name, "v": [to_plain(getattr(value, f), depth + 1) for f in fields]}
    if hasattr(t, "__array__"):
        return to_plain(np.asarray(value), depth)
    if hasattr(t, "__index__"):
        return to_plain(int(value.__index__()), depth)
    if hasattr(t, "__float__"):
        return to_plain(float(value), depth)
    if isinstance(value, (set, frozenset, range)):
        return {"$": "opaque", "type": name, "repr": bounded(repr(value), 200)}
    try:
        text = repr(value)
    except Exception:
        text = f"<{name}>"
    return {"$": "opaque", "type": name, "repr": bounded(text, 200)}


def _float_text(v: float) -> Any:
    return v if math.isfinite(v) else repr(v)  # "nan", "inf", "-inf"


def _nd_items(arr: np.ndarray) -> Any:
    if arr.dtype.kind == "f":
        out = arr.astype(float)
        if np.all(np.isfinite(out)):
            return out.tolist()
        return np.vectorize(_float_text, otypes=[object])(out).tolist() if out.ndim else _float_text(float(out))
    return arr.tolist()


def from_plain(data: Any, depth: int = 0) -> Any:
    """Rebuild in the parent what :func:`to_plain` sent: fresh builtins, arrays and rapp values.

    Anything malformed raises ``ValueError``.

    Examples
    --------
    >>> from_plain(to_plain((1, [2.5, "s"], np.zeros(2))))
    (1, [2.5, 's'], array([0., 0.]))
    """
    if depth > _MAX_DEPTH + 2:
        raise ValueError("nested too deeply")
    if data is None or isinstance(data, (bool, int, str)):
        return data
    if isinstance(data, float):
        return data
    if isinstance(data, list):
        return [from_plain(v, depth + 1) for v in data]
    if not isinstance(data, dict):
        raise ValueError(f"not plain data: {type(data).__name__}")
    tag = data.get("$")
    if tag == "float":
        return float(data["v"])
    if tag == "tuple":
        return tuple(from_plain(v, depth + 1) for v in data["v"])
    if tag == "dict":
        out = {}
        for k, v in data["v"]:
            key = from_plain(k, depth + 1)
            try:
                hash(key)
            except TypeError:
                key = repr(key)
            out[key] = from_plain(v, depth + 1)
        return out
    if tag in ("nd", "npscalar"):
        dtype = np.dtype(str(data["dtype"]))
        if dtype.kind not in _ND_KINDS:
            raise ValueError("not a numeric dtype")
        items = data["v"]
        arr = np.array(_floats_back(items) if dtype.kind == "f" else items, dtype=dtype)
        if tag == "npscalar":
            return arr.reshape(()).dtype.type(arr.reshape(())[()])
        shape = tuple(int(s) for s in data["shape"])
        return arr.reshape(shape)
    if tag == "ndobj":
        shape = tuple(int(s) for s in data["shape"])
        flat = [from_plain(v, depth + 1) for v in data["v"]]
        arr = np.empty(len(flat), dtype=object)
        arr[:] = flat
        return arr.reshape(shape)
    if tag == "rapp" and data.get("type") == "Scenario":
        from rapp.scenario import load_scenario
        mapping = from_plain(data["v"][0], depth + 1)
        try:
            return load_scenario(mapping)
        except Exception:  # the judge loads it again and says what is wrong with it
            return mapping
    if tag == "rapp":
        from rapp.arm import Arm
        from rapp.obstacles import Circle, Polygon
        kind = {"Circle": Circle, "Polygon": Polygon, "Arm": Arm}[str(data["type"])]
        args = [from_plain(v, depth + 1) for v in data["v"]]
        if kind is Arm and args[1] is not None:
            args[1] = [tuple(lim) if lim is not None else None for lim in args[1]]
        return kind(*args)
    if tag == "opaque":
        return Opaque(bounded(str(data["type"]), 100), bounded(str(data["repr"]), 200))
    raise ValueError(f"unknown tag {tag!r}")


def _floats_back(items: Any) -> Any:
    if isinstance(items, list):
        return [_floats_back(v) for v in items]
    return float(items) if isinstance(items, str) else items


# --- the child's side ------------------------------------------------------------------------

# Linux x86-64 system calls that reach another process or leave the process group.
_BLOCKED_SYSCALLS = {
    "kill": 62, "tkill": 200, "tgkill": 234, "rt_sigqueueinfo": 129, "rt_tgsigqueueinfo": 297,
    "pidfd_send_signal": 424, "pidfd_open": 434, "pidfd_getfd": 438, "ptrace": 101,
    "process_vm_readv": 310, "process_vm_writev": 311, "setsid": 112, "setpgid": 109,
    "kcmp": 312,
}


def _install_seccomp() -> bool:
    """Refuse (EPERM) the system calls above for this process and its descendants; True if done."""
    if sys.platform != "linux" or platform.machine() != "x86_64":
        return False
    try:
        libc = ctypes.CDLL(None, use_errno=True)

        class SockFilter(ctypes.Structure):
            _fields_ = [("code", ctypes.c_ushort), ("jt", ctypes.c_ubyte), ("jf", ctypes.c_ubyte),
                        ("k", ctypes.c_uint)]

        class SockFprog(ctypes.Structure):
            _fields_ = [("len", ctypes.c_ushort), ("filter", ctypes.POINTER(SockFilter))]

        ld_abs, jeq, jge, ret = 0x20, 0x15, 0x35, 0x06
        allow, deny = 0x7FFF0000, 0x00050000 | 1  # SECCOMP_RET_ALLOW, SECCOMP_RET_ERRNO | EPERM
        numbers = sorted(_BLOCKED_SYSCALLS.values())
        prog = [(ld_abs, 0, 0, 4),                      # the architecture
                (jeq, 1, 0, 0xC000003E),                # AUDIT_ARCH_X86_64, else:
                (ret, 0, 0, 0x80000000),                # kill the process (another ABI)
                (ld_abs, 0, 0, 0),                      # the system call number
                (jge, len(numbers) + 1, 0, 0x40000000)]  # the x32 ABI: refused
        for i, nr in enumerate(numbers):
            prog.append((jeq, len(numbers) - i, 0, nr))
        prog += [(ret, 0, 0, allow), (ret, 0, 0, deny)]
        arr = (SockFilter * len(prog))(*[SockFilter(*p) for p in prog])
        fprog = SockFprog(len(prog), arr)
        if libc.prctl(38, 1, 0, 0, 0) != 0:  # PR_SET_NO_NEW_PRIVS
            return False
        return libc.prctl(22, 2, ctypes.byref(fprog), 0, 0) == 0  # PR_SET_SECCOMP, FILTER
    except Exception:
        return False


def _vm_size() -> int:
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("VmSize:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return 0


def confine(limits: Limits) -> None:
    """Limit the calling process (the child): own group, CPU, memory, seccomp. Best effort."""
    try:
        os.setsid()
    except OSError:
        pass
    import resource
    cpu = limits.cpu if limits.cpu is not None else limits.wall + 1.0
    try:
        resource.setrlimit(resource.RLIMIT_CPU, (max(1, math.ceil(cpu)), max(1, math.ceil(cpu)) + 1))
    except (ValueError, OSError):
        pass
    try:
        soft, hard = resource.getrlimit(resource.RLIMIT_AS)
        want = _vm_size() + int(limits.memory)
        if hard == resource.RLIM_INFINITY or want < hard:
            resource.setrlimit(resource.RLIMIT_AS, (want, hard))
    except (ValueError, OSError):
        pass
    try:
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
    except (ValueError, OSError):
        pass
    _install_seccomp()


def _read_exact(fd: int, n: int) -> bytes:
    chunks, got = [], 0
    while got < n:
        b = os.read(fd, n - got)
        if not b:
            raise EOFError
        chunks.append(b)
        got += len(b)
    return b"".join(chunks)


def send_message(fd: int, payload: bytes) -> None:
    """Write one length-prefixed message to ``fd`` (the child's side of the protocol)."""
    data = struct.pack("<Q", len(payload)) + payload
    view = memoryview(data)
    while view:
        n = os.write(fd, view)
        view = view[n:]


def _describe_exception(exc: BaseException) -> str:
    try:
        text = str(exc)
    except BaseException:
        text = "<unprintable>"
    return bounded(f"{type(exc).__name__}: {bounded(text, 1500)}" if text else type(exc).__name__, 1800)


def serve(objects: Any, rfd: int, wfd: int) -> None:
    """The child's loop: answer the parent's requests about ``objects`` until the pipe closes.

    ``objects`` is a mapping from key to the reader's object (or a callable returning it).
    """
    while True:
        try:
            (n,) = struct.unpack("<Q", _read_exact(rfd, 8))
            op, key, args = pickle.loads(_read_exact(rfd, n))
        except BaseException:
            return
        try:
            if op == "keys":
                reply = {"ok": to_plain([str(k) for k in objects.keys()])}
            else:
                obj = objects[key]
                if op == "plain":
                    reply = {"ok": to_plain(obj)}
                elif op == "call":
                    reply = {"ok": to_plain(obj(*args))}
                elif op == "signature":
                    reply = {"ok": _signature_problem(obj, *args)}
                elif op == "callable":
                    reply = {"ok": bool(callable(obj))}
                else:
                    reply = {"err": "Died: unknown request"}
            payload = json.dumps(reply, allow_nan=False).encode()
        except BaseException as exc:  # SystemExit, KeyboardInterrupt, MemoryError from the reader too
            try:
                payload = json.dumps({"raised": _describe_exception(exc)}).encode()
            except BaseException:
                payload = b'{"raised": "an exception that could not be described"}'
        if len(payload) > MAX_REPLY:
            payload = json.dumps({"big": len(payload)}).encode()
        try:
            send_message(wfd, payload)
        except BaseException:
            return


def _signature_problem(fn: Any, call: str, n_args: int) -> str | None:
    import inspect
    try:
        sig = inspect.signature(fn)
    except (TypeError, ValueError):
        return None  # a builtin or a C function: just try it
    try:
        sig.bind(*range(n_args))
    except TypeError:
        return bounded(f"your function takes {sig}, but this exercise calls it as {call}.", 500)
    return None


# --- the parent's side -----------------------------------------------------------------------

class Sandbox:
    """A child process holding a reader's objects; see the module docstring.

    Use :meth:`of` to fork one from this process (the objects already live here), or
    :meth:`attach` for a child started by :mod:`rapp.grading` from a submission file.
    Every request has the time left of ``limits.wall``; a request that runs out of it kills
    the child's whole process group and raises :class:`TimedOut`.
    """

    def __init__(self, pid: int, rfd: int, wfd: int, limits: Limits, popen: Any = None):
        self.pid, self._rfd, self._wfd, self.limits, self.popen = pid, rfd, wfd, limits, popen
        self.deadline = time.monotonic() + limits.wall
        self.dead: str | None = None

    @classmethod
    def of(cls, objects: dict, limits: Limits) -> "Sandbox":
        """Fork a child that holds ``objects`` (already in this process's memory)."""
        p_read, c_write = os.pipe()
        c_read, p_write = os.pipe()
        sys.stdout.flush(), sys.stderr.flush()
        pid = os.fork()
        if pid == 0:  # the child: never returns
            try:
                os.close(p_read), os.close(p_write)
                signal.signal(signal.SIGINT, signal.SIG_DFL)
                confine(limits)
                devnull = os.open(os.devnull, os.O_RDWR)
                os.dup2(devnull, 0), os.dup2(devnull, 1), os.dup2(devnull, 2)
                sys.stdout = sys.stderr = io.StringIO()
                serve(objects, c_read, c_write)
            finally:
                os._exit(0)  # skip the parent's atexit handlers (a Jupyter kernel has several)
        os.close(c_read), os.close(c_write)
        return cls(pid, p_read, p_write, limits)

    @classmethod
    def attach(cls, popen: Any, rfd: int, wfd: int, limits: Limits) -> "Sandbox":
        """Wrap a child started with :class:`subprocess.Popen` that runs :func:`serve`."""
        return cls(popen.pid, rfd, wfd, limits, popen)

    def __enter__(self) -> "Sandbox":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def _request(self, op: str, key: Any, args: Any = ()) -> Any:
        if self.dead:
            raise Died(self.dead)
        try:
            payload = pickle.dumps((op, key, args))
        except Exception as exc:
            raise Died(f"the arguments could not be sent ({type(exc).__name__})") from None
        try:
            send_message(self._wfd, payload)
        except OSError:
            self._kill("the child ended")
            raise Died(self._why_dead()) from None
        reply = self.receive()
        if "ok" in reply:
            try:
                return from_plain(reply["ok"])
            except Exception as exc:
                self._kill("malformed reply")
                raise Died(f"it sent something that is not plain data ({bounded(exc, 200)})") from None
        if "raised" in reply:
            raise Raised(bounded(str(reply["raised"])))
        if "big" in reply:
            raise Raised(f"ValueError: the value is too large to check ({reply['big']:,} bytes)")
        self._kill("malformed reply")
        raise Died("it sent something that is not a reply")

    def receive(self) -> dict:
        """The child's next reply as a dict (bounded, within the deadline), or a SandboxError."""
        header = self._read(8)
        (n,) = struct.unpack("<Q", header)
        if n > MAX_REPLY + 1024:
            self._kill("reply too large")
            raise Died("it sent more data than a reply may hold")
        body = self._read(n)
        try:
            reply = json.loads(body)
        except Exception:
            reply = None
        if not isinstance(reply, dict):
            self._kill("malformed reply")
            raise Died("it sent something that is not a reply")
        return reply

    def _read(self, n: int) -> bytes:
        chunks, got = [], 0
        while got < n:
            left = self.deadline - time.monotonic()
            if left <= 0:
                self._kill("timeout")
                raise TimedOut(f"no answer within {self.limits.wall:g} s")
            try:
                ready, _, _ = select.select([self._rfd], [], [], left)
            except InterruptedError:
                continue
            if not ready:
                continue
            b = os.read(self._rfd, min(n - got, 1 << 20))
            if not b:
                why = self._why_dead()
                self._kill(why)
                if "CPU" in why:
                    raise TimedOut(why)
                raise Died(why)
            chunks.append(b)
            got += len(b)
        return b"".join(chunks)

    def _why_dead(self) -> str:
        status = self._wait(0.5)
        if status is None:
            return "it closed its connection to the checker"
        if os.WIFSIGNALED(status):
            sig = os.WTERMSIG(status)
            if sig in (signal.SIGXCPU, signal.SIGKILL) and self._cpu_spent():
                return "it used up its CPU time"
            return f"it was ended by signal {signal.Signals(sig).name}" if sig in signal.Signals._value2member_map_ \
                else f"it was ended by signal {sig}"
        code = os.WEXITSTATUS(status)
        return f"it ended the process (exit code {code}; did it call exit?)"

    def _cpu_spent(self) -> bool:
        return getattr(self, "_rusage_cpu", 0.0) >= (self.limits.cpu if self.limits.cpu is not None
                                                     else self.limits.wall + 1.0) - 0.05

    def _wait(self, timeout: float) -> int | None:
        if hasattr(self, "_status"):
            return self._status
        end = time.monotonic() + timeout
        while True:
            try:
                pid, status, rusage = os.wait4(self.pid, os.WNOHANG)
            except ChildProcessError:
                return None
            if pid:
                self._status = status
                self._rusage_cpu = rusage.ru_utime + rusage.ru_stime
                if self.popen is not None:
                    self.popen.returncode = os.waitstatus_to_exitcode(status)
                return status
            if time.monotonic() >= end:
                return None
            time.sleep(0.005)

    def _kill(self, why: str) -> None:
        if self.dead is None:
            self.dead = why
        for target in (lambda: os.killpg(self.pid, signal.SIGKILL), lambda: os.kill(self.pid, signal.SIGKILL)):
            try:
                target()
            except (ProcessLookupError, PermissionError, OSError):
                pass
        self._wait(2.0)

    def close(self) -> None:
        """Kill the child and everything it started; idempotent."""
        self._kill("closed")
        for fd in (self._rfd, self._wfd):
            try:
                os.close(fd)
            except OSError:
                pass
        self._rfd = self._wfd = -1

    # The requests the judges make.
    def plain(self, key: Any) -> Any:
        """The object as plain data (see :func:`to_plain`)."""
        return self._request("plain", key)

    def call(self, key: Any, args: tuple) -> Any:
        """``objects[key](*args)`` in the child, as plain data; args are sent as copies."""
        return self._request("call", key, tuple(args))

    def is_callable(self, key: Any) -> bool:
        return bool(self._request("callable", key))

    def keys(self) -> list[str]:
        return list(self._request("keys", None))

    def signature_problem(self, key: Any, call: str, n_args: int) -> str | None:
        return self._request("signature", key, (call, n_args))


class Remote:
    """A reader's function as the judges see it: calls run in the sandbox, results are plain data.

    Calling it may raise :class:`SandboxError`; :func:`rapp.exercises.check` turns that into a
    verdict.
    """

    def __init__(self, box: Sandbox, key: Any):
        self._box, self._key = box, key

    def __call__(self, *args: Any) -> Any:
        return self._box.call(self._key, args)

    def signature_problem(self, call: str, n_args: int) -> str | None:
        return self._box.signature_problem(self._key, call, n_args)

    @property
    def time_left(self) -> float:
        return max(0.0, self._box.deadline - time.monotonic())
