"""The ``morphserve`` command: run the service or a worker, or talk to a running service.

::

    morphserve serve [--host H] [--port P] [--data-dir D] [--scheduler tcp://...] [--workers N]
    morphserve worker [--scheduler tcp://host:8786] [--nworkers N] [--memory-limit 4GiB]
    morphserve processes [--json]
    morphserve describe alignment.rigid [--json]
    morphserve execute alignment.rigid --input source=a.npy --input target=b.json \\
        --param allow_reflection=false --wait --output result.json
    morphserve execute deformation.arap --input mesh=scan.ply --input handles=h.json \\
        --wait --output result.glb
    morphserve jobs [--status running] [--process alignment.rigid] [--limit 20] [--json]
    morphserve status JOB [--json] | results JOB [--output FILE] | dismiss JOB
    morphserve keys add NAME | keys revoke NAME | keys list   [--file F]

The client commands go through the SDK (:mod:`morphserve`) to ``--url`` (default
``$MORPHSERVE_URL``, else http://127.0.0.1:8000); ``--json`` prints one JSON document for
scripts. Errors go to stderr (``error: <title>: <detail>``) with an exit status of their own
(:class:`Exit`, listed by ``morphserve --help``). They send ``$MORPHSERVE_API_KEY`` as the
bearer key when it is set. ``keys`` edits the API keys file (``--file``, default
``$MORPHSERVE_API_KEYS_FILE``): ``add`` prints the new key once and stores only its hash.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from collections.abc import Callable, Sequence
from enum import IntEnum
from pathlib import Path
from typing import Any

import numpy as np

from morphserve import (
    DEFAULT_URL,
    JOB_STATES,
    APIError,
    Client,
    InvalidInput,
    JobDismissed,
    JobFailed,
    JobStatus,
    MorphserveError,
    NotFound,
    ResultNotReady,
    Results,
    ServiceUnavailable,
    TransportError,
    WaitTimeout,
    __version__,
)

__all__ = ["Exit", "build_parser", "connect", "exit_status", "main", "parse_input",
           "parse_param", "worker_argv"]


class Exit(IntEnum):
    """The exit statuses of the ``morphserve`` command, one per kind of outcome, so that a
    script can tell them apart (the ``--help`` epilog and the README list them)."""

    OK = 0
    """Done."""
    ERROR = 1
    """Any other refusal of the service (a full queue, a wrong API key ...) or local error."""
    USAGE = 2
    """The command line is wrong (an unknown option, an unreadable input file)."""
    INVALID_INPUT = 3
    """The service refused an input (422); the input and why are on stderr."""
    NOT_FOUND = 4
    """No such process, job or output (404)."""
    UNREACHABLE = 5
    """The service cannot be reached, or is not ready (503)."""
    JOB_FAILED = 6
    """The job ran and failed, ran out of time, or was dismissed."""
    TIMEOUT = 7
    """``--timeout`` passed before the job ended; the job goes on."""
    INTERRUPTED = 130
    """Ctrl-C (128 + SIGINT, as shells report it)."""


_EXIT_WORDS = {
    Exit.OK: "done",
    Exit.ERROR: "the service refused for another reason (such as a full queue)",
    Exit.USAGE: "wrong usage (an unknown option, an unreadable input file)",
    Exit.INVALID_INPUT: "the service refused an input",
    Exit.NOT_FOUND: "no such process, job or output",
    Exit.UNREACHABLE: "the service cannot be reached or is not ready",
    Exit.JOB_FAILED: "the job failed or was dismissed",
    Exit.TIMEOUT: "--timeout passed before the job ended (it goes on)",
    Exit.INTERRUPTED: "interrupted (Ctrl-C)",
}


def exit_status(error: MorphserveError) -> Exit:
    """The exit status of a command that raised ``error``."""
    if isinstance(error, InvalidInput):
        return Exit.INVALID_INPUT
    if isinstance(error, (JobFailed, JobDismissed)):
        return Exit.JOB_FAILED
    if isinstance(error, NotFound) and not isinstance(error, ResultNotReady):
        return Exit.NOT_FOUND
    if isinstance(error, (TransportError, ServiceUnavailable)):
        return Exit.UNREACHABLE
    if isinstance(error, WaitTimeout):
        return Exit.TIMEOUT
    return Exit.ERROR


def _epilog() -> str:
    lines = ["exit status:"]
    lines += [f"  {int(code):<4} {words}" for code, words in _EXIT_WORDS.items()]
    return "\n".join(lines)


class UsageError(Exception):
    """The command line is wrong in a way argparse cannot see (exit status 2)."""


def connect(url: str) -> Client:
    """The SDK client the client commands use; tests replace this to inject a transport."""
    return Client(url)


# -- argument types ----------------------------------------------------------------------


def _split(text: str, form: str) -> tuple[str, str]:
    name, sep, value = text.partition("=")
    if not sep or not name:
        raise argparse.ArgumentTypeError(f"expected {form}, got {text!r}")
    return name, value


#: Geometry files sent as they are (uploaded), read by the service.
GEOMETRY_FILES = (".ply", ".obj", ".stl", ".off", ".glb")


def parse_input(text: str) -> tuple[str, Any]:
    """``NAME=FILE`` → (name, value): a .json file's JSON value, a .npy file's array, or a
    geometry file (.ply, .obj, .stl, .off, .glb) as its path, which the SDK uploads."""
    name, file = _split(text, "NAME=FILE")
    path = Path(file)
    suffix = path.suffix.lower()
    if suffix not in (".json", ".npy", *GEOMETRY_FILES):
        raise argparse.ArgumentTypeError(
            f"expected a .json, .npy, {', '.join(GEOMETRY_FILES)} file for input {name!r}, "
            f"got {file!r}"
        )
    try:
        if suffix in GEOMETRY_FILES:
            if not path.is_file():
                raise argparse.ArgumentTypeError(f"cannot read {file}: no such file")
            return name, path
        if suffix == ".npy":
            return name, np.load(path, allow_pickle=False)
        with path.open(encoding="utf-8") as stream:
            return name, json.load(stream)
    except OSError as error:
        raise argparse.ArgumentTypeError(f"cannot read {file}: {error.strerror or error}") from None
    except ValueError as error:  # bad JSON, or not an .npy file, or an object array
        raise argparse.ArgumentTypeError(f"cannot read {file}: {error}") from None


def _reject_constant(constant: str) -> Any:
    raise ValueError(f"{constant} is not JSON")


def parse_param(text: str) -> tuple[str, Any]:
    """``NAME=VALUE`` → (name, value): VALUE read as JSON when it is JSON, else a string.

    ``k=3`` gives 3, ``k=true`` True, ``k=[1,2]`` a list, ``k=svd`` and ``k=NaN`` strings.
    """
    name, value = _split(text, "NAME=VALUE")
    try:
        return name, json.loads(value, parse_constant=_reject_constant)
    except ValueError:
        return name, value


def _positive_int(text: str) -> int:
    try:
        number = int(text)
    except ValueError:
        number = 0
    if number < 1:
        raise argparse.ArgumentTypeError(f"expected a whole number of 1 or more, got {text!r}")
    return number


def _port(text: str) -> int:
    number = _positive_int(text)
    if number > 65535:
        raise argparse.ArgumentTypeError(f"expected a port up to 65535, got {text!r}")
    return number


def _seconds(text: str) -> float:
    try:
        seconds = float(text)
    except ValueError:
        seconds = -1.0
    if not seconds >= 0 or seconds == float("inf"):
        raise argparse.ArgumentTypeError(f"expected seconds, 0 or more, got {text!r}")
    return seconds


# -- output ------------------------------------------------------------------------------


def _table(headers: Sequence[str], rows: Sequence[Sequence[Any]]) -> str:
    cells = [list(headers)] + [["" if c is None else str(c) for c in row] for row in rows]
    widths = [max(len(row[i]) for row in cells) for i in range(len(headers))]
    return "\n".join(
        "  ".join(c.ljust(w) for c, w in zip(row, widths, strict=True)).rstrip() for row in cells
    )


def _schema_type(schema: Any) -> str:
    """A short name for a JSON Schema: ``number``, ``array[array[number]]``, ``integer|null``."""
    if not isinstance(schema, dict):
        return "any"
    kind = schema.get("type")
    if isinstance(kind, list):
        return "|".join(map(str, kind))
    if kind == "array" and isinstance(schema.get("items"), dict):
        return f"array[{_schema_type(schema['items'])}]"
    if kind:
        return str(kind)
    for key in ("anyOf", "oneOf"):
        if isinstance(schema.get(key), list):
            return "|".join(_schema_type(s) for s in schema[key])
    if "$ref" in schema:
        return str(schema["$ref"]).rsplit("/", 1)[-1]
    if "enum" in schema:
        return "enum"
    return "any"


def _input_use(description: dict[str, Any]) -> str:
    schema = description.get("schema") or {}
    if (description.get("minOccurs", 1) or 0) >= 1:
        return "required"
    if isinstance(schema, dict) and "default" in schema:
        return f"default {json.dumps(schema['default'])}"
    return "optional"


def _when(moment: Any) -> str | None:
    """A time as `status` and `jobs` both print it: ISO 8601 to the second, with its zone."""
    return moment.isoformat(timespec="seconds") if moment is not None else None


def _status_lines(status: JobStatus) -> str:
    fields = [
        ("job", status.job_id),
        ("process", status.process_id),
        ("status", status.status),
        ("progress", None if status.progress is None else f"{status.progress}%"),
        ("message", status.message),
        ("created", _when(status.created)),
        ("started", _when(status.started)),
        ("finished", _when(status.finished)),
        ("updated", _when(status.updated)),
    ]
    return "\n".join(
        f"{name:<9}{'' if value is None else value}".rstrip() for name, value in fields
    )


def _print_json(document: Any) -> None:
    """One JSON document on stdout, for scripts (``--json``)."""
    print(json.dumps(document))


#: ``--output`` suffixes written by :meth:`Results.save` (anything else: the JSON document).
SAVED_SUFFIXES = (".glb", ".npy", *(s for s in GEOMETRY_FILES if s != ".glb"))


def _put_results(results: Results, output: Path | None) -> None:
    """Print the results as JSON, or write them to ``output`` in the format its suffix names:
    .glb (the result's geometry as glTF), .ply, .obj, .stl, .off (its mesh or points, as the
    SDK's ``Results.save`` writes them), .npy (the one array output), else JSON."""
    if output is None:
        print(json.dumps(results.to_json()))
        return
    try:
        if output.suffix.lower() in SAVED_SUFFIXES:
            results.save(output)
        else:
            output.write_text(json.dumps(results.to_json()) + "\n", encoding="utf-8")
    except OSError as error:
        raise MorphserveError(f"cannot write {output}: {error.strerror or error}") from None
    except ValueError as error:  # .npy of several arrays, a mesh file of no geometry
        raise UsageError(f"{error} (--output FILE.json writes them all)") from None
    print(f"results written to {output}", file=sys.stderr)


# -- commands ----------------------------------------------------------------------------


def _serve(args: argparse.Namespace) -> int:
    from service.server import run  # the web stack loads only for this command

    run(
        host=args.host,
        port=args.port,
        data_dir=args.data_dir,
        scheduler=args.scheduler,
        workers=args.workers,
    )
    return 0


def _keys(args: argparse.Namespace) -> int:
    from service.auth import KeyFileError, key_line, new_key, parse_keys

    if args.file is None:
        raise UsageError("name the keys file with --file or MORPHSERVE_API_KEYS_FILE")
    if args.action != "list" and not args.name:
        raise UsageError(f"keys {args.action} needs the key's NAME")
    path: Path = args.file
    try:
        text = path.read_text(encoding="utf-8") if path.exists() else ""
        names = set(parse_keys(text, str(path)).values())
    except (OSError, KeyFileError) as error:
        raise MorphserveError(str(error)) from None
    if args.action == "list":
        for name in sorted(names):
            print(name)
        return 0
    if args.action == "add":
        if args.name in names:
            raise MorphserveError(f"{path} already has a key named {args.name!r}; revoke it "
                                  "first or choose another name")
        key = new_key()
        try:
            line = key_line(args.name, key)
        except KeyFileError as error:
            raise UsageError(str(error)) from None
        sep = "" if not text or text.endswith("\n") else "\n"
        _write_private(path, text + sep + line + "\n")
        print(key)
        print(f"key {args.name!r} added to {path}; it is shown only this once", file=sys.stderr)
        return 0
    if args.name not in names:  # revoke
        raise MorphserveError(f"{path} has no key named {args.name!r}")
    kept = [ln for ln in text.splitlines()
            if ln.split("#", 1)[0].split()[:1] != [args.name]]
    _write_private(path, "\n".join(kept) + "\n")
    print(f"key {args.name!r} revoked", file=sys.stderr)
    return 0


def _write_private(path: Path, text: str) -> None:
    """Replace ``path`` atomically with ``text``.

    A new file is readable by its owner only; a file that exists keeps its permission bits
    (a keys file made readable for a container's user stays so after ``keys add|revoke``,
    as ``sed -i`` or an editor would keep it).
    """
    tmp = path.with_name(path.name + ".tmp")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        try:
            mode = path.stat().st_mode & 0o777
        except FileNotFoundError:
            mode = 0o600
        fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
        os.fchmod(fd, mode)  # exactly this mode, whatever the umask
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(text)
        os.replace(tmp, path)
    except OSError as error:
        raise MorphserveError(f"cannot write {path}: {error.strerror or error}") from None


def _cpu_count() -> int:
    try:
        return len(os.sched_getaffinity(0))  # the CPUs this process may use (cgroups, taskset)
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def worker_argv(
    scheduler: str,
    *,
    nworkers: int | None = None,
    memory_limit: str | None = None,
    name: str | None = None,
) -> list[str]:
    """The ``dask worker`` command line ``morphserve worker`` runs: one thread per process.

    ``nworkers`` defaults to the number of CPUs this process may use; ``memory_limit`` (per
    process, such as ``4GiB``) and ``name`` are passed on when given.
    """
    argv = [sys.executable, "-m", "distributed.cli.dask_worker", scheduler]
    argv += ["--nthreads", "1", "--nworkers", str(nworkers or _cpu_count())]
    if memory_limit is not None:
        argv += ["--memory-limit", memory_limit]
    if name is not None:
        argv += ["--name", name]
    return argv


def _worker(args: argparse.Namespace) -> int:
    scheduler = args.scheduler or os.environ.get("MORPHSERVE_SCHEDULER")
    if not scheduler:
        raise UsageError("worker needs --scheduler tcp://HOST:8786 or MORPHSERVE_SCHEDULER")
    argv = worker_argv(
        scheduler, nworkers=args.nworkers, memory_limit=args.memory_limit, name=args.name
    )
    sys.stdout.flush()
    sys.stderr.flush()
    os.execv(argv[0], argv)
    return 0  # not reached: execv replaces this process


def _processes(args: argparse.Namespace) -> int:
    with connect(args.url) as client:
        processes = client.processes()
    if args.json:
        _print_json([{"id": p.id, "title": p.title, "description": p.description,
                      "version": p.version, "jobControlOptions": list(p.job_control_options)}
                     for p in processes])
        return 0
    print(_table(["ID", "TITLE"], [(p.id, p.title) for p in processes]))
    return 0


def _describe(args: argparse.Namespace) -> int:
    with connect(args.url) as client:
        process = client.describe(args.process)
    if args.json:
        _print_json(process.raw)
        return 0
    version = f" (version {process.version})" if process.version else ""
    print(f"{process.id}: {process.title}{version}")
    if process.description:
        print(process.description)
    inputs = [
        (name, _schema_type(spec.get("schema")), _input_use(spec), spec.get("title", ""))
        for name, spec in process.inputs.items()
    ]
    outputs = [
        (name, _schema_type(spec.get("schema")), spec.get("title", ""))
        for name, spec in process.outputs.items()
    ]
    print("\ninputs:")
    print(_indent(_table(["NAME", "TYPE", "USE", "TITLE"], inputs)))
    print("\noutputs:")
    print(_indent(_table(["NAME", "TYPE", "TITLE"], outputs)))
    return 0


def _indent(text: str) -> str:
    return "\n".join("  " + line for line in text.splitlines())


def _execute(args: argparse.Namespace) -> int:
    if not args.wait and (args.timeout is not None or args.output is not None):
        raise UsageError("execute: --timeout and --output need --wait")
    inputs: dict[str, Any] = {}
    for name, value in [*args.inputs, *args.params]:
        if name in inputs:
            raise UsageError(f"execute: input {name!r} given twice")
        inputs[name] = value
    with connect(args.url) as client:
        job = client.execute(args.process, time_limit=args.time_limit, **inputs)
        if not args.wait:
            if args.json:
                status = job.submitted_status
                _print_json(status.raw if status is not None and status.raw else
                            {"jobID": job.id, "processID": job.process_id})
            else:
                print(job.id)
            return 0
        try:
            job.wait(timeout=args.timeout, progress=not args.no_progress)
        except KeyboardInterrupt:
            print(
                f"interrupted; job {job.id} goes on (morphserve dismiss {job.id} stops it)",
                file=sys.stderr,
            )
            return Exit.INTERRUPTED
        except WaitTimeout as error:
            print(
                f"error: {error} It goes on: 'morphserve status {job.id}' follows it, "
                f"'morphserve dismiss {job.id}' stops it.",
                file=sys.stderr,
            )
            return Exit.TIMEOUT
        results = job.results()
        if args.json:
            document: dict[str, Any] = {"jobID": job.id, "processID": job.process_id,
                                        "status": "successful"}
            if args.output is not None:
                _put_results(results, args.output)
                document["output"] = str(args.output)
            else:
                document["results"] = results.to_json()
            _print_json(document)
        else:
            _put_results(results, args.output)
    return 0


def _jobs(args: argparse.Namespace) -> int:
    with connect(args.url) as client:
        jobs = client.jobs(status=args.status, process=args.process, limit=args.limit)
    if args.json:
        _print_json([j.raw for j in jobs])
        return 0
    rows = [
        (
            j.job_id,
            j.process_id,
            j.status,
            None if j.progress is None else f"{j.progress}%",
            _when(j.created),
            j.message,
        )
        for j in jobs
    ]
    print(_table(["JOB", "PROCESS", "STATUS", "PROGRESS", "CREATED", "MESSAGE"], rows))
    return 0


def _status(args: argparse.Namespace) -> int:
    with connect(args.url) as client:
        status = client.job(args.job).status()
    print(json.dumps(status.raw) if args.json else _status_lines(status))
    return 0


def _results(args: argparse.Namespace) -> int:
    with connect(args.url) as client:
        try:
            results = client.job(args.job).results()
        except ResultNotReady as error:  # the service's text, not the SDK's job.result() hint
            cause = error.__cause__
            raise (cause if isinstance(cause, ResultNotReady) else error) from None
        _put_results(results, args.output)
    return 0


def _dismiss(args: argparse.Namespace) -> int:
    with connect(args.url) as client:
        status = client.job(args.job).dismiss()
    print(f"{status.job_id} {status.status}")
    return 0


# -- parser ------------------------------------------------------------------------------


def build_parser() -> argparse.ArgumentParser:
    """The parser of the ``morphserve`` command; defaults come from the environment now."""
    parser = argparse.ArgumentParser(
        prog="morphserve",
        description="A geometry job service over OGC API - Processes: run it, or talk to it.",
        epilog=_epilog(),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument(
        "--url",
        default=os.environ.get("MORPHSERVE_URL") or DEFAULT_URL,
        help=f"the service, for the client commands (default: $MORPHSERVE_URL, else {DEFAULT_URL})",
    )
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    # --url is also accepted after a client command; SUPPRESS keeps the global value otherwise
    remote = argparse.ArgumentParser(add_help=False)
    remote.add_argument("--url", default=argparse.SUPPRESS, help="the service")
    # --json: one JSON document on stdout instead of the text for people
    scripted = argparse.ArgumentParser(add_help=False)
    scripted.add_argument("--json", action="store_true",
                          help="print one JSON document (for scripts) instead of text")

    def command(name: str, run: Callable[[argparse.Namespace], int], text: str, **kw: Any) -> Any:
        sub = commands.add_parser(name, help=text, description=text, epilog=_epilog(),
                                  formatter_class=argparse.RawDescriptionHelpFormatter, **kw)
        sub.set_defaults(run=run)
        return sub

    serve = command("serve", _serve, "Run the HTTP service (with an embedded Dask cluster).")
    serve.add_argument(
        "--host",
        default=os.environ.get("HOST") or "127.0.0.1",
        help="(default: $HOST, else %(default)s)",
    )
    serve.add_argument(
        "--port",
        type=_port,
        default=os.environ.get("PORT") or "8000",
        help="(default: $PORT, else 8000)",
    )
    serve.add_argument(
        "--data-dir",
        type=Path,
        help="job store and results (default: $MORPHSERVE_DATA_DIR, else ./data)",
    )
    serve.add_argument(
        "--scheduler",
        help="an external Dask scheduler, tcp://HOST:8786 (default: $MORPHSERVE_SCHEDULER, "
        "else an embedded cluster)",
    )
    serve.add_argument(
        "--workers",
        type=_positive_int,
        help="processes of the embedded cluster (default: $MORPHSERVE_WORKERS, else 2)",
    )

    worker = command("worker", _worker, "Run Dask workers for an external scheduler.")
    worker.add_argument("--scheduler", help="tcp://HOST:8786 (default: $MORPHSERVE_SCHEDULER)")
    worker.add_argument(
        "--nworkers",
        type=_positive_int,
        help="worker processes, one thread each (default: the CPUs)",
    )
    worker.add_argument("--memory-limit", help="per worker process, such as 4GiB (default: auto)")
    worker.add_argument("--name", help="worker name; a process number is appended")

    command("processes", _processes, "List the processes.", parents=[remote, scripted])

    describe = command(
        "describe", _describe, "Show a process's inputs and outputs.",
        parents=[remote, scripted],
    )
    describe.add_argument("process", metavar="ID")

    execute = command("execute", _execute, "Start a job (and wait for it).",
                      parents=[remote, scripted])
    execute.add_argument("process", metavar="ID")
    execute.add_argument(
        "--input",
        dest="inputs",
        action="append",
        type=parse_input,
        default=[],
        metavar="NAME=FILE",
        help="an input from a .json (a JSON value) or .npy file, or a geometry file "
        "(.ply, .obj, .stl, .off, .glb) uploaded as it is; repeatable",
    )
    execute.add_argument(
        "--param",
        dest="params",
        action="append",
        type=parse_param,
        default=[],
        metavar="NAME=VALUE",
        help="an input; VALUE is read as JSON when it is JSON, else as a string; repeatable",
    )
    execute.add_argument(
        "--wait", action="store_true", help="wait for the job and print its results"
    )
    execute.add_argument(
        "--timeout", type=_seconds, metavar="S", help="with --wait: give up after S seconds"
    )
    execute.add_argument(
        "--output", type=Path, metavar="FILE", help="with --wait: write the results here: "
        ".glb for the result's geometry (glTF binary), .ply, .obj, .stl or .off for its mesh "
        "or points, .npy for its one array, else JSON"
    )
    execute.add_argument("--no-progress", action="store_true", help="with --wait: no progress bar")
    execute.add_argument(
        "--time-limit", type=_seconds, metavar="S",
        help="stop the job after S seconds of running (it then fails)",
    )

    jobs = command("jobs", _jobs, "List jobs.", parents=[remote, scripted])
    jobs.add_argument("--status", action="append", choices=JOB_STATES, help="repeatable")
    jobs.add_argument("--process", metavar="ID")
    jobs.add_argument(
        "--limit", type=_positive_int, metavar="N", help="at most N jobs (default: 1000)"
    )

    keys = command("keys", _keys, "Add, revoke or list API keys (the keys file holds hashes).")
    keys.add_argument("action", choices=("add", "revoke", "list"))
    keys.add_argument("name", nargs="?", metavar="NAME", help="the key's owner (add, revoke)")
    keys.add_argument(
        "--file",
        type=Path,
        default=os.environ.get("MORPHSERVE_API_KEYS_FILE") or None,
        help="the keys file (default: $MORPHSERVE_API_KEYS_FILE)",
    )

    for name, run, text in [
        ("status", _status, "Show where a job stands."),
        ("results", _results, "Print a job's results as JSON."),
        ("dismiss", _dismiss, "Cancel a job, or remove a finished one."),
    ]:
        sub = command(name, run, text, parents=[remote, scripted] if name == "status"
                      else [remote])
        sub.add_argument("job", metavar="JOB")
        if name == "results":
            sub.add_argument("--output", type=Path, metavar="FILE", help="write the results "
                             "here: .glb (geometry), .ply, .obj, .stl, .off (mesh or points), "
                             ".npy (the one array) or JSON")
    return parser


def _report(error: MorphserveError, url: str) -> None:
    if isinstance(error, APIError):
        print(
            f"error: {error.title}: {error.detail}" if error.detail else f"error: {error.title}",
            file=sys.stderr,
        )
        for field in error.errors:
            print(f"  {field.get('input', '?')}: {field.get('message', '')}", file=sys.stderr)
    elif isinstance(error, TransportError):
        print(f"error: cannot reach {url}: {error}", file=sys.stderr)
    else:
        print(f"error: {error}", file=sys.stderr)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command; return its exit status (:class:`Exit`)."""
    try:
        parser = build_parser()
        try:
            args = parser.parse_args(argv)
        except SystemExit as stop:  # --help, --version, or a usage error already printed
            return (stop.code if isinstance(stop.code, int) else
                    Exit.OK if stop.code is None else Exit.USAGE)
        try:
            return int(args.run(args))
        except UsageError as error:
            parser.print_usage(sys.stderr)
            print(f"{parser.prog}: error: {error}", file=sys.stderr)
            return Exit.USAGE
        except MorphserveError as error:
            _report(error, args.url)
            return exit_status(error)
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return Exit.INTERRUPTED


if __name__ == "__main__":
    sys.exit(main())
