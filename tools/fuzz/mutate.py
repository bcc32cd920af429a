#!/usr/bin/env python3
"""Mutation fuzzer for the lagrange command line (docs/reliability.md).

Mutates the example models (examples/**/*.lag) deterministically from a seed, runs every
command on every mutant with a time limit and checks the contract of docs/cli.md:

* the exit code is one of 0..5 (101 is a panic, a negative code a signal);
* nothing says "panicked" on standard error;
* no command runs past the time limit (a hang);
* an exit 1 (the input is wrong) says where: `FILE:LINE:COL` or `line L, column C`, unless
  the message says the model lacks something as a whole (ABSENCE_MESSAGES: nothing to point at);
* exit 4 (lagrange disagrees with itself) is a bug by the contract, so it is a failure too;
* the model file is unchanged afterwards, and the output stays under a size limit.

Only the Python 3 standard library is used: CI has Python 3 and the Rust toolchain only.
The time budget (--seconds) is checked before each mutant starts, so the run is bounded
whatever the machine's speed; the mutants themselves depend only on the seed.

Failures whose signature matches a line of the known-failures file (tools/fuzz/known.txt)
are reported as tolerated; any other failure makes the exit status 1.
"""

import argparse
import concurrent.futures
import fnmatch
import hashlib
import math
import os
import random
import re
import resource
import shutil
import signal
import sys
import tempfile
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

# Each command is run on each mutant (the mutant's path is appended).
COMMANDS = [
    ("check", ["check"]),
    ("eom", ["eom"]),
    ("eom-json", ["eom", "--format", "json"]),
    ("solve", ["solve"]),
    ("reactions", ["reactions"]),
    ("equilibria", ["equilibria"]),
    ("linearize", ["linearize"]),
    ("simulate", ["simulate", "--t-end", "0.5"]),
]

# Exit-1 messages that concern the model as a whole: there is no line to point at.
ABSENCE_MESSAGES = [
    re.compile(r"the model asks for no reaction"),
]

DOCUMENTED_EXITS = {0, 1, 2, 3, 4, 5}
WALL_FACTOR = 3  # wall-clock backstop, as a multiple of the processor-time limit
MEMORY_LIMIT = 4 << 30  # address space per run; beyond it an allocation fails (a signal)

# Replacement values for numbers: extremes, degenerate and malformed.
NUMBERS = [
    "0", "-1", "1", "1e308", "-1e308", "1e-320", "1e309", "0.0000001", "3.14159265358979",
    "123456789012345678901234567890", "0/0", "1/0", "-0", "2.5e", "1..2", ".5", "5.",
    "NaN", "inf", "(0)",
]

# Tokens inserted at random places: brackets (often unbalanced), operators, punctuation.
TOKENS = [
    "(", ")", "[", "]", "{", "}", ",", "=", "*", "^", "/", "+", "-", ":", ".", "'", "#",
    '"', ";", "..", "**", "->", "\t", "\n", " ", "0", "t", "pi", "sin(", "d(", "__",
]


# Models whose Lagrange route (eom, solve, reactions) needs more processor time than a run
# here has before it stops at its work limit: the Whipple bicycle's `norm()` contact takes
# about 11 s to be refused (issue 18; it is solved by `linearize`, Kane's route, in 0.06 s).
SLOW_EXAMPLES = {"whipple-bicycle.lag"}


def load_examples():
    """The example models, sorted, as (relative path, bytes), without SLOW_EXAMPLES."""
    paths = sorted(p for p in (ROOT / "examples").rglob("*.lag") if p.name not in SLOW_EXAMPLES)
    return [(p.relative_to(ROOT).as_posix(), p.read_bytes()) for p in paths]


def vocabulary(examples):
    """Every identifier of the examples: keywords, names, for renaming and insertion."""
    words = set()
    for _, data in examples:
        words.update(re.findall(r"[A-Za-z_][A-Za-z_0-9']*", data.decode("utf-8", "replace")))
    return sorted(words)


# ---- mutations: each takes (rng, text bytes, words) and returns bytes ------------------------

def lines_of(data):
    return data.split(b"\n")


def m_delete_line(rng, data, words):
    lines = lines_of(data)
    del lines[rng.randrange(len(lines))]
    return b"\n".join(lines)


def m_duplicate_line(rng, data, words):
    lines = lines_of(data)
    i = rng.randrange(len(lines))
    lines.insert(rng.randrange(len(lines) + 1), lines[i])
    return b"\n".join(lines)


def m_swap_lines(rng, data, words):
    lines = lines_of(data)
    i, j = rng.randrange(len(lines)), rng.randrange(len(lines))
    lines[i], lines[j] = lines[j], lines[i]
    return b"\n".join(lines)


def spans(pattern, data):
    return [m.span() for m in re.finditer(pattern, data)]


def replace_span(data, span, new):
    return data[: span[0]] + new + data[span[1]:]


def m_number(rng, data, words):
    found = spans(rb"(?<![A-Za-z_0-9.])\d+(?:\.\d*)?(?:[eE][-+]?\d+)?", data)
    if not found:
        return m_insert_token(rng, data, words)
    return replace_span(data, rng.choice(found), rng.choice(NUMBERS).encode())


def identifier_spans(data):
    return spans(rb"(?<![A-Za-z_0-9])[A-Za-z_][A-Za-z_0-9]*", data)


def m_rename(rng, data, words):
    found = identifier_spans(data)
    if not found:
        return m_insert_token(rng, data, words)
    span = rng.choice(found)
    new = rng.choice(words + ["x", "zz_undeclared", "theta2", "N"])
    if rng.random() < 0.5:
        # Rename every occurrence: the model stays consistent but names change roles.
        old = data[span[0]: span[1]]
        return re.sub(rb"(?<![A-Za-z_0-9])" + re.escape(old) + rb"(?![A-Za-z_0-9])",
                      new.encode(), data)
    return replace_span(data, span, new.encode())


def m_drop_identifier(rng, data, words):
    found = identifier_spans(data)
    if not found:
        return m_truncate(rng, data, words)
    return replace_span(data, rng.choice(found), b"")


def m_insert_token(rng, data, words):
    pos = rng.randrange(len(data) + 1)
    token = rng.choice(TOKENS + words) if rng.random() < 0.7 else rng.choice(words)
    sep = b" " if rng.random() < 0.5 else b""
    return data[:pos] + sep + token.encode() + sep + data[pos:]


def m_brackets(rng, data, words):
    pos = rng.randrange(len(data) + 1)
    return data[:pos] + rng.choice([b"(" * 50, b")" * 3, b"((((", b"[", b"]]", b"(" * 2000]) + data[pos:]


def m_truncate(rng, data, words):
    return data[: rng.randrange(len(data) + 1)]


def m_non_utf8(rng, data, words):
    pos = rng.randrange(len(data) + 1)
    return data[:pos] + rng.choice([b"\xff", b"\xc3", b"\xed\xa0\x80", b"\x00", b"\xfe\xff"]) + data[pos:]


def m_long_line(rng, data, words):
    lines = lines_of(data)
    i = rng.randrange(len(lines))
    kind = rng.randrange(4)
    if kind == 0:  # a very long line of the same statement
        lines[i] = (lines[i] + b" ") * 200
    elif kind == 1:  # a very long identifier
        lines.insert(i, b"parameters " + b"a" * 20000 + b" = 1")
    elif kind == 2:  # a long sum in an expression
        lines.insert(i, b"parameters zq = " + b" + ".join([b"1"] * 3000))
    else:  # a deeply nested expression
        lines.insert(i, b"parameters zq = " + b"(" * 300 + b"1" + b")" * 300)
    return b"\n".join(lines)


def m_unicode(rng, data, words):
    pos = rng.randrange(len(data) + 1)
    return data[:pos] + rng.choice(["θ", "é", "\u200b", "ﬁ", "𝑥", "\u202e", "₂"]).encode() + data[pos:]


MUTATIONS = [
    m_delete_line, m_duplicate_line, m_swap_lines, m_number, m_number, m_rename, m_rename,
    m_drop_identifier, m_insert_token, m_insert_token, m_brackets, m_truncate, m_non_utf8,
    m_long_line, m_unicode,
]


def make_mutant(seed, index, examples, words):
    """Mutant `index`: the example it comes from, the mutations applied and its bytes."""
    rng = random.Random(f"{seed}:{index}")
    name, data = examples[index % len(examples)]
    applied = []
    for _ in range(rng.choice([1, 1, 1, 2, 3])):
        mutation = rng.choice(MUTATIONS)
        data = mutation(rng, data, words)
        applied.append(mutation.__name__[2:])
    return name, applied, data


# ---- running one command ----------------------------------------------------------------------

class Outcome:
    def __init__(self, code, seconds, stdout_size, stderr_text, timed_out, changed):
        self.code = code
        self.seconds = seconds  # processor time (user + system), the measure of the limit
        self.stdout_size = stdout_size
        self.stderr_text = stderr_text
        self.timed_out = timed_out
        self.changed = changed


def limits(timeout, output_limit):
    def apply():
        cpu = math.ceil(timeout)
        resource.setrlimit(resource.RLIMIT_CPU, (cpu, cpu + 1))
        resource.setrlimit(resource.RLIMIT_AS, (MEMORY_LIMIT, MEMORY_LIMIT))
        resource.setrlimit(resource.RLIMIT_FSIZE, (output_limit, output_limit))
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
    return apply


def run_once(binary, args, model, workdir, timeout, output_limit):
    """Run `binary args model` in workdir under the limits.

    The time limit is processor time (RLIMIT_CPU: SIGXCPU), so that a loaded machine does not
    turn a slow run into a hang; a wall-clock backstop of WALL_FACTOR times the limit catches a
    process that waits without computing.
    """
    import subprocess  # local: keeps the module's top readable as the fuzzer's description

    out_path, err_path = workdir / "stdout", workdir / "stderr"
    before = (workdir / model).read_bytes()
    start = time.monotonic()
    with open(out_path, "wb") as out, open(err_path, "wb") as err:
        proc = subprocess.Popen(
            [binary] + args + [model], cwd=workdir, stdin=subprocess.DEVNULL, stdout=out,
            stderr=err, preexec_fn=limits(timeout, output_limit), start_new_session=True,
            env=dict(os.environ, NO_COLOR="1", RUST_BACKTRACE="0"))
        timed_out = False
        while True:
            pid, status, usage = os.wait4(proc.pid, os.WNOHANG)
            if pid:
                break
            if time.monotonic() - start > WALL_FACTOR * timeout:
                timed_out = True
                os.killpg(proc.pid, signal.SIGKILL)
                pid, status, usage = os.wait4(proc.pid, 0)
                break
            time.sleep(0.01)
        proc.returncode = os.waitstatus_to_exitcode(status)
    seconds = usage.ru_utime + usage.ru_stime
    # SIGXCPU at the soft limit; SIGKILL at the hard one if SIGXCPU was ignored.
    if proc.returncode == -signal.SIGXCPU or (proc.returncode == -signal.SIGKILL
                                              and seconds >= timeout):
        timed_out = True
    with open(err_path, "rb") as err:
        stderr_text = err.read(64 << 10).decode("utf-8", "replace")
    model_path = workdir / model
    changed = not model_path.exists() or model_path.read_bytes() != before
    return Outcome(proc.returncode, seconds, out_path.stat().st_size, stderr_text, timed_out,
                   changed)


def judge(outcome, model, output_limit):
    """The failures of one run, as signature kinds (empty when the run kept the contract)."""
    kinds = []
    code = outcome.code
    if outcome.timed_out:
        kinds.append("hang")
    elif code == -signal.SIGXFSZ:
        kinds.append("output-limit")
    elif code < 0:
        kinds.append(f"signal={signal.Signals(-code).name}")
    elif code == 101:
        kinds.append("exit=101 panic")
    elif code not in DOCUMENTED_EXITS:
        kinds.append(f"exit={code} undocumented")
    if "panicked" in outcome.stderr_text and code != 101:
        kinds.append("panicked-message")
    if code == 1 and not outcome.timed_out and not located(outcome.stderr_text, model):
        kinds.append("exit=1 missing-location")
    if code == 4:
        kinds.append("exit=4 disagreement")
    if outcome.changed:
        kinds.append("input-changed")
    if outcome.stdout_size >= output_limit and "output-limit" not in kinds:
        kinds.append("output-limit")
    return kinds


def located(stderr_text, model):
    if re.search(re.escape(model) + r":\d+:\d+", stderr_text):
        return True
    if re.search(r"line \d+, column \d+", stderr_text):
        return True
    return any(p.search(stderr_text) for p in ABSENCE_MESSAGES)


# ---- the campaign -----------------------------------------------------------------------------

class Campaign:
    def __init__(self, opts, examples, words, known):
        self.opts = opts
        self.examples = examples
        self.words = words
        self.known = known
        self.lock = threading.Lock()
        self.mutants = 0
        self.runs = 0
        self.by_exit = {}
        self.failures = {}  # signature -> [count, first reproductions]
        self.slow_pairs = set()  # (example, command) too slow unmutated: skipped on mutants
        self.slowest = (0.0, "")

    def run_model(self, label, name, data, commands):
        base = Path(name).name
        with tempfile.TemporaryDirectory(prefix="lagrange-fuzz-") as tmp:
            workdir = Path(tmp)
            (workdir / base).write_bytes(data)
            results = []
            for cname, args in commands:
                outcome = run_once(self.opts.binary, args, base, workdir, self.opts.timeout,
                                   self.opts.output_limit)
                if outcome.changed:
                    (workdir / base).write_bytes(data)
                results.append((cname, args, outcome))
                self.record(label, name, base, data, cname, args, outcome)
            return results

    def record(self, label, name, base, data, cname, args, outcome):
        kinds = judge(outcome, base, self.opts.output_limit)
        with self.lock:
            self.runs += 1
            key = "timeout" if outcome.timed_out else str(outcome.code)
            self.by_exit[key] = self.by_exit.get(key, 0) + 1
            if outcome.seconds > self.slowest[0] and not outcome.timed_out:
                self.slowest = (outcome.seconds, f"{cname} on {label}")
            if label.startswith("original") and outcome.timed_out:
                # Too slow unmutated: the pair is skipped on mutants; the example is named,
                # so that known.txt can tolerate exactly the known slow ones.
                kinds = [f"slow-original {Path(name).name}"]
            for kind in kinds:
                signature = f"{kind} command={cname}"
                entry = self.failures.setdefault(signature, [0, []])
                entry[0] += 1
                if len(entry[1]) < self.opts.keep:
                    entry[1].append(self.save(signature, label, name, base, data, args, outcome))

    def save(self, signature, label, name, base, data, args, outcome):
        slug = re.sub(r"[^A-Za-z0-9]+", "-", signature).strip("-")
        folder = Path(self.opts.failures) / slug
        folder.mkdir(parents=True, exist_ok=True)
        digest = hashlib.sha1(data).hexdigest()[:10]
        model = folder / f"{digest}-{base}"
        model.write_bytes(data)
        command = " ".join([self.opts.binary] + args + [str(model)])
        (folder / f"{digest}-{base}.txt").write_text(
            f"from: {label} ({name})\ncommand: {command}\nexit: {outcome.code}"
            f"{' (killed at the time limit)' if outcome.timed_out else ''}\n"
            f"seconds: {outcome.seconds:.1f}\nstderr (first 4 KB):\n{outcome.stderr_text[:4096]}\n")
        return command

    def baseline(self, pool):
        """Every command on every unmutated example; a pair over the time limit is skipped later."""
        jobs = [pool.submit(self.run_model, f"original {name}", name, data, COMMANDS)
                for name, data in self.examples]
        for (name, _), job in zip(self.examples, jobs):
            for cname, _, outcome in job.result():
                if outcome.timed_out:
                    self.slow_pairs.add((name, cname))

    def mutant(self, index):
        name, applied, data = make_mutant(self.opts.seed, index, self.examples, self.words)
        commands = [c for c in COMMANDS if (name, c[0]) not in self.slow_pairs]
        with self.lock:
            self.mutants += 1
        self.run_model(f"mutant {index} of {name} ({'+'.join(applied)})", name, data, commands)

    def fuzz(self, pool, deadline):
        index = 0
        running = set()
        while True:
            while len(running) < self.opts.jobs and time.monotonic() < deadline:
                if self.opts.mutants and index >= self.opts.mutants:
                    break
                running.add(pool.submit(self.mutant, index))
                index += 1
            if not running:
                return
            done, running = concurrent.futures.wait(
                running, return_when=concurrent.futures.FIRST_COMPLETED)
            for job in done:
                job.result()

    def is_known(self, signature):
        return any(fnmatch.fnmatchcase(signature, pattern) for pattern in self.known)


def read_known(path):
    if not path or not Path(path).exists():
        return []
    patterns = []
    for line in Path(path).read_text().splitlines():
        line = line.split("#", 1)[0].strip()
        if line:
            patterns.append(line)
    return patterns


def report(campaign, elapsed):
    c = campaign
    print(f"\nlagrange fuzz: seed {c.opts.seed}, {c.mutants} mutants, {c.runs} runs "
          f"(including {len(c.examples)} unmutated examples × {len(COMMANDS)} commands) "
          f"in {elapsed:.0f} s, {c.opts.jobs} at a time")
    print("runs by exit code: " + ", ".join(
        f"{k}: {v}" for k, v in sorted(c.by_exit.items(), key=lambda kv: kv[0])))
    print(f"slowest run: {c.slowest[0]:.1f} s of processor time ({c.slowest[1]})")
    if c.slow_pairs:
        print(f"over the {c.opts.timeout:g} s limit unmutated, so not run on their mutants: "
              + ", ".join(f"{cmd} on {name}" for name, cmd in sorted(c.slow_pairs)))
    new = {s: e for s, e in c.failures.items() if not c.is_known(s)}
    tolerated = {s: e for s, e in c.failures.items() if c.is_known(s)}
    if tolerated:
        print(f"\nKNOWN FAILURES (tolerated by {c.opts.known}; fix them and remove the line):")
        show(tolerated)
    if new:
        print(f"\nNEW FAILURES (mutants and details saved under {c.opts.failures}):")
        show(new)
    else:
        print("\nno new failures")
    return 1 if new else 0


def show(failures):
    for signature, (count, examples) in sorted(failures.items()):
        print(f"  {signature}: {count} run(s)")
        for command in examples:
            print(f"    reproduce: {command}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--binary", default=default_binary(), help="the lagrange executable")
    parser.add_argument("--seconds", type=float, default=180,
                        help="stop starting mutants after this long (default 180)")
    parser.add_argument("--seed", type=int, default=1, help="the mutants depend only on this")
    parser.add_argument("--mutants", type=int, default=0, help="at most this many (0: no limit)")
    parser.add_argument("--timeout", type=float, default=10, help="processor seconds per run (default 10)")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1,
                        help="mutants run at once (default: the number of cores)")
    parser.add_argument("--output-limit", type=int, default=32 << 20,
                        help="bytes one run may print (default 32 MiB)")
    parser.add_argument("--failures", default=str(target_dir() / "fuzz-failures"),
                        help="where failing mutants are saved")
    parser.add_argument("--keep", type=int, default=3, help="reproductions kept per signature")
    parser.add_argument("--known", default=str(ROOT / "tools" / "fuzz" / "known.txt"),
                        help="known failures to tolerate, one signature pattern a line")
    opts = parser.parse_args()
    opts.binary = str(Path(opts.binary).resolve())
    if not Path(opts.binary).is_file():
        sys.exit(f"mutate.py: no lagrange binary at {opts.binary}; build it (cargo build) "
                 f"or pass --binary")
    shutil.rmtree(opts.failures, ignore_errors=True)

    examples = load_examples()
    campaign = Campaign(opts, examples, vocabulary(examples), read_known(opts.known))
    start = time.monotonic()
    with concurrent.futures.ThreadPoolExecutor(max_workers=opts.jobs) as pool:
        campaign.baseline(pool)
        campaign.fuzz(pool, start + opts.seconds)
    sys.exit(report(campaign, time.monotonic() - start))


def target_dir():
    return Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))


def default_binary():
    return str(target_dir() / "debug" / "lagrange")


if __name__ == "__main__":
    main()
