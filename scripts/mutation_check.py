#!/usr/bin/env python3
"""Mutation check of rbaa's test suite (called by scripts/mutation_check.sh; see its header).

Enumerates small source mutations of src/{sim,diff,geometry,opt,eval,rigid}/*.cpp in the committed
HEAD of a checkout, samples some of them reproducibly, and for each one rebuilds a scratch copy of
the tree incrementally and runs ctest: a mutant the suite does not notice is a hole in the tests.
Standard library only.
"""

import argparse
import collections
import fcntl
import hashlib
import io
import os
import re
import shutil
import subprocess
import sys
import tarfile
import time

MODULES = ["sim", "diff", "geometry", "opt", "eval", "rigid"]
CMAKE_FLAGS = ["-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release", "-DRBAA_BUILD_BENCHMARKS=OFF",
               # The tests load librbaa.so at run time: relinking a dozen test programs after every
               # one-file change would cost more than the change.
               "-DCMAKE_LINK_DEPENDS_NO_SHARED=ON"]
TEST_ENV = {"OMP_NUM_THREADS": "2", "OPENBLAS_NUM_THREADS": "1"}
TEST_TIMEOUT_S = 300

# ----------------------------------------------------------------------------------------------
# A small C++ lexer: enough to find operators, numbers and statements outside comments, string and
# character literals and preprocessor lines.

PUNCTUATORS = sorted(
    ["<<=", ">>=", "<=>", "->*", "...", "::", "->", "++", "--", "<<", ">>", "<=", ">=", "==",
     "!=", "&&", "||", "+=", "-=", "*=", "/=", "%=", "&=", "|=", "^=", ".*"],
    key=len, reverse=True)
KEYWORDS = {"return", "case", "throw", "else", "do", "new", "delete", "co_return", "sizeof",
            "operator", "and", "or", "not", "if", "while", "for", "switch", "const", "constexpr",
            "auto", "static", "using", "typename", "template", "goto", "default"}
STRING_PREFIXES = {"u8", "u", "U", "L"}
RAW_PREFIXES = {"R", "u8R", "uR", "UR", "LR"}


class Token:
    __slots__ = ("kind", "text", "start", "end", "line")

    def __init__(self, kind, text, start, end, line):
        self.kind, self.text, self.start, self.end, self.line = kind, text, start, end, line

    def __repr__(self):
        return f"{self.kind}:{self.text}@{self.line}"


NUMBER_RE = re.compile(r"\.?[0-9](?:[eEpP][+-]|['\w.])*")
IDENT_RE = re.compile(r"[A-Za-z_]\w*")


def lex(text):
    tokens = []
    i, n, line = 0, len(text), 1
    line_start = True  # only whitespace since the last newline: a '#' starts a directive
    while i < n:
        c = text[i]
        if c == "\n":
            line += 1
            i += 1
            line_start = True
            continue
        if c in " \t\r\f\v":
            i += 1
            continue
        if c == "\\" and text.startswith("\n", i + 1):
            i += 2
            line += 1
            continue
        if text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
            continue
        if text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            line += text.count("\n", i, j)
            i = j
            continue
        if c == "#" and line_start:
            # A directive runs to the end of the line, continued by backslashes.
            while i < n and text[i] != "\n":
                if text[i] == "\\" and text.startswith("\n", i + 1):
                    line += 1
                    i += 1
                i += 1
            continue
        line_start = False
        start = i
        m = IDENT_RE.match(text, i)
        if m:
            word = m.group(0)
            j = m.end()
            if word in RAW_PREFIXES and text.startswith('"', j):
                k = text.find("(", j)
                delim = text[j + 1:k]
                end = text.find(")" + delim + '"', k)
                end = n if end < 0 else end + len(delim) + 2
                tokens.append(Token("string", text[start:end], start, end, line))
                line += text.count("\n", start, end)
                i = end
                continue
            if word in STRING_PREFIXES and j < n and text[j] in "\"'":
                i = j
                c = text[j]  # fall through to the literal below, keeping start
            else:
                tokens.append(Token("ident", word, start, j, line))
                i = j
                continue
        if c in "\"'":
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            end = min(j + 1, n)
            kind = "string" if c == '"' else "char"
            tokens.append(Token(kind, text[start:end], start, end, line))
            i = end
            continue
        if c.isdigit() or (c == "." and i + 1 < n and text[i + 1].isdigit()):
            m = NUMBER_RE.match(text, i)
            tokens.append(Token("number", m.group(0), i, m.end(), line))
            i = m.end()
            continue
        for p in PUNCTUATORS:
            if text.startswith(p, i):
                break
        else:
            p = c
        tokens.append(Token("punct", p, i, i + len(p), line))
        i += len(p)
    return tokens


# ----------------------------------------------------------------------------------------------
# Mutation operators.

ARITH_SWAP = {"+": "-", "-": "+", "*": "/", "/": "*", "+=": "-=", "-=": "+=", "*=": "/=",
              "/=": "*="}
COMPARISON_SWAP = {"<": "<=", "<=": "<", ">": ">=", ">=": ">", "==": "!=", "!=": "=="}
COMPARISONS = set(COMPARISON_SWAP)
ASSIGNMENTS = {"=", "+=", "-=", "*=", "/=", "%=", "&=", "|=", "^=", "<<=", ">>="}
OPEN = {"(": ")", "[": "]", "{": "}"}
CLOSE = {")", "]", "}"}


class Mutant:
    def __init__(self, path, kind, start, end, replacement, text):
        self.path, self.kind = path, kind
        self.start, self.end, self.replacement = start, end, replacement
        self.line = text.count("\n", 0, start) + 1
        ls = text.rfind("\n", 0, start) + 1
        le = text.find("\n", end)
        le = len(text) if le < 0 else le
        self.before = " ".join(text[ls:le].split())
        self.after = " ".join((text[ls:start] + replacement + text[end:le]).split())
        self.id = None  # set once every mutant of the file is known

    @property
    def folder(self):
        return self.path.split("/")[1]

    @property
    def where(self):
        return f"{self.path}:{self.line}"

    @property
    def mutation(self):
        return f"{self.before} -> {self.after}"

    def apply(self, text):
        return text[:self.start] + self.replacement + text[self.end:]


def spaced(text, tok):
    """A binary operator as clang-format writes it: whitespace on both sides."""
    return (tok.start > 0 and text[tok.start - 1].isspace() and tok.end < len(text)
            and text[tok.end].isspace())


def operand_end(tok):
    """Can this token end an operand (so that an operator after it is binary)?"""
    if tok is None:
        return False
    if tok.kind in ("number", "string", "char"):
        return True
    if tok.kind == "ident":
        return tok.text not in KEYWORDS or tok.text in ("this",)
    return tok.text in (")", "]")


class Scanner:
    """Bracket-aware scans over a token list; template angle brackets are guessed (an unspaced
    '<' right after a name opens one)."""

    def __init__(self, text, tokens):
        self.text, self.t = text, tokens

    def is_binary(self, k):
        tok = self.t[k]
        return k > 0 and spaced(self.text, tok) and operand_end(self.t[k - 1]) and \
            self.t[k - 1].text != "operator"

    def forward(self, k, stop):
        """Index of the first token from k at nesting depth 0 for which stop(j) holds, or of a
        closing bracket that leaves the scanned level (returned negated-1 so callers can tell)."""
        stack = []
        j = k
        while j < len(self.t):
            tok = self.t[j]
            if not stack and stop(j):
                return j
            s = tok.text
            if s in OPEN:
                stack.append(OPEN[s])
            elif s in CLOSE:
                if not stack:
                    return -1 - j
                while stack and stack[-1] == ">":
                    stack.pop()
                if stack:
                    stack.pop()
            elif s == "<" and not spaced(self.text, tok) and j > 0 and \
                    self.t[j - 1].kind == "ident" and self.t[j - 1].end == tok.start:
                stack.append(">")
            elif s in (">", ">>") and stack and stack[-1] == ">" and not spaced(self.text, tok):
                stack.pop()
                if s == ">>" and stack and stack[-1] == ">":
                    stack.pop()
            j += 1
        return -1 - j

    def backward_statement_start(self, k):
        """Index of the first token of the statement holding token k, or None when k sits inside
        brackets or a comma expression."""
        j = k - 1
        while j >= 0:
            s = self.t[j].text
            if s in (";", "{", "}") or (s == ":" and j > 0 and self.t[j - 1].kind != "punct") \
                    or (self.t[j].kind == "ident" and s in ("else", "do")):
                return j + 1
            if s == ",":
                return None
            if s in ("(", "["):
                return None
            if s in (")", "]"):
                depth = 0
                while j >= 0:
                    if self.t[j].text in (")", "]"):
                        depth += 1
                    elif self.t[j].text in ("(", "["):
                        depth -= 1
                        if depth == 0:
                            break
                    j -= 1
                if j > 0 and self.t[j - 1].text in ("if", "for", "while", "switch"):
                    return j_after_close(self.t, j)
            j -= 1
        return 0


def j_after_close(tokens, open_index):
    depth = 0
    for j in range(open_index, len(tokens)):
        if tokens[j].text == "(":
            depth += 1
        elif tokens[j].text == ")":
            depth -= 1
            if depth == 0:
                return j + 1
    return len(tokens)


def number_value(s):
    """(value, is_float, suffix) of a decimal literal, or None for hex, binary, octal and the odd
    ones."""
    s = s.replace("'", "")
    m = re.fullmatch(r"((?:\d+\.\d*|\.\d+|\d+)(?:[eE][+-]?\d+)?)([fFlLuU]*)", s)
    if not m or s.lower().startswith(("0x", "0b")):
        return None
    body, suffix = m.groups()
    is_float = any(ch in body for ch in ".eE")
    if not is_float and len(body) > 1 and body.startswith("0"):
        return None  # octal
    return (float(body) if is_float else int(body)), is_float, suffix


def format_float(v):
    s = repr(v)
    if "e" in s:
        mantissa, exponent = s.split("e")
        return f"{mantissa}e{int(exponent)}"  # 2e-09 -> 2e-9
    return s if "." in s else s + ".0"


def enumerate_file(path, text):
    toks = lex(text)
    sc = Scanner(text, toks)
    mutants = []
    string_lines = {t.line for t in toks if t.kind in ("string", "char")}

    def add(kind, start, end, replacement):
        mutants.append(Mutant(path, kind, start, end, replacement, text))

    arith_or_cmp = set(ARITH_SWAP) | COMPARISONS
    for k, tok in enumerate(toks):
        s = tok.text
        prev = toks[k - 1] if k > 0 else None
        nxt = toks[k + 1] if k + 1 < len(toks) else None

        # Arithmetic operator swapped (binary + - * / and their compound assignments).
        if tok.kind == "punct" and s in ARITH_SWAP and sc.is_binary(k):
            if not (s in ("+", "+=") and tok.line in string_lines):  # string concatenation
                add("arith", tok.start, tok.end, ARITH_SWAP[s])

        # Comparison swapped.
        if tok.kind == "punct" and s in COMPARISONS and sc.is_binary(k):
            add("compare", tok.start, tok.end, COMPARISON_SWAP[s])

        # Term dropped: "a + b * c" -> "a"; a "+=" or "-=" statement removed.
        if tok.kind == "punct" and s in ("+", "-") and sc.is_binary(k) and \
                tok.line not in string_lines:
            def term_stop(j):
                u = toks[j]
                if u.text in ("+", "-") and sc.is_binary(j):
                    return True
                return u.text in (";", ",", "?", ":", "&&", "||", "<<", ">>", "&", "|", "^") or \
                    u.text in ASSIGNMENTS or (u.text in COMPARISONS and spaced(text, u))
            e = sc.forward(k + 1, term_stop)
            e = e if e >= 0 else -1 - e
            if e > k + 1:
                ws = tok.start
                while ws > 0 and text[ws - 1] in " \t":
                    ws -= 1
                add("drop-term", ws, toks[e - 1].end, "")
        if tok.kind == "punct" and s in ("+=", "-=") and sc.is_binary(k):
            b = sc.backward_statement_start(k)
            e = sc.forward(k + 1, lambda j: toks[j].text == ";")
            if b is not None and b < k and e >= 0:
                add("drop-term", toks[b].start, toks[e].end, "{}")

        # Loop bound changed: for (...; i < n; ...) -> i < n - 1.
        if tok.kind == "ident" and s == "for" and nxt is not None and nxt.text == "(":
            semi1 = sc.forward(k + 2, lambda j: toks[j].text == ";")
            if semi1 >= 0:
                semi2 = sc.forward(semi1 + 1, lambda j: toks[j].text == ";")
                if semi2 >= 0:
                    for j in range(semi1 + 1, semi2):
                        if toks[j].text in ("<", "<=") and sc.is_binary(j):
                            e = sc.forward(j + 1, lambda q: toks[q].text in (
                                ";", "&&", "||", ",", "?"))
                            if e == semi2 and e > j + 1:
                                add("loop-bound", toks[e - 1].end, toks[e - 1].end, " - 1")
                            break

        # Numeric constant scaled: floats x2 (1.0 -> 1.1); integers next to an arithmetic or
        # comparison operator x2.
        if tok.kind == "number":
            nv = number_value(s)
            if nv is not None:
                v, is_float, suffix = nv
                if is_float and v != 0:
                    add("constant", tok.start, tok.end,
                        (format_float(1.1) if v == 1 else format_float(v * 2)) + suffix)
                elif not is_float and v != 0:
                    context = [u for u in (prev, nxt) if u is not None and u.kind == "punct"]
                    if any(u.text in arith_or_cmp and spaced(text, u) for u in context):
                        add("constant", tok.start, tok.end, str(v * 2) + suffix)

        # Sign flipped: a unary minus removed ...
        if tok.kind == "punct" and s == "-" and nxt is not None and nxt.start == tok.end and \
                not operand_end(prev) and not (prev is not None and prev.text == "operator") and \
                (nxt.kind in ("ident", "number") or nxt.text == "("):
            add("sign", tok.start, tok.end, "")
        # ... or added in front of a numeric value returned or assigned.
        if (s == "return" and tok.kind == "ident") or \
                (s == "=" and tok.kind == "punct" and operand_end(prev) and
                 prev.kind in ("ident", "punct")):
            e = sc.forward(k + 1, lambda j: toks[j].text in (";", ","))
            if e > k + 1:
                body = toks[k + 1:e]
                numeric = any((u.kind == "number" and number_value(u.text) and
                               number_value(u.text)[1]) or
                              (u.text in ("+", "-", "*", "/") and sc.is_binary(k + 1 + i))
                              for i, u in enumerate(body))
                unsuitable = any(u.kind in ("string", "char") or u.text in (
                    "{", "}", "?", "&&", "||", "!", "<<", "new", "[&", "[=") or
                    (u.text in COMPARISONS and spaced(text, u)) for u in body) or \
                    body[0].text == "["
                if numeric and not unsuitable:
                    add("sign", body[0].start, body[-1].end,
                        "-(" + text[body[0].start:body[-1].end] + ")")

    # Stable ids: independent of line numbers, so that editing elsewhere does not rename them.
    seen = collections.Counter()
    for m in mutants:
        key = (m.path, m.kind, m.before, m.after)
        m.id = hashlib.sha1(repr(key + (seen[key],)).encode()).hexdigest()[:8]
        seen[key] += 1
    return mutants


# ----------------------------------------------------------------------------------------------
# Sampling and the equivalent-mutants file.

def rank(seed, mutant_id):
    return hashlib.sha256(f"{seed}:{mutant_id}".encode()).hexdigest()


def sample(mutants, count, seed):
    """Stratified by folder: every folder gets one mutant (when count allows), the rest goes to
    the folders in proportion to their candidates (largest remainders); within a folder the
    mutants with the lowest hash of (seed, id) are taken."""
    by_folder = collections.defaultdict(list)
    for m in mutants:
        by_folder[m.folder].append(m)
    for ms in by_folder.values():
        ms.sort(key=lambda m: rank(seed, m.id))
    folders = sorted(by_folder, key=lambda f: rank(seed, f))
    count = min(count, len(mutants))
    quota = {f: 0 for f in folders}
    if count < len(folders):
        for f in folders[:count]:
            quota[f] = 1
    else:
        for f in folders:
            quota[f] = 1
        rest = count - len(folders)
        total = max(1, sum(len(by_folder[f]) - 1 for f in folders))
        shares = {f: rest * (len(by_folder[f]) - 1) / total for f in folders}
        for f in folders:
            quota[f] += int(shares[f])
        left = count - sum(quota.values())
        for f in sorted(folders, key=lambda f: -(shares[f] - int(shares[f])))[:left]:
            quota[f] += 1
    chosen = [m for f in folders for m in by_folder[f][:quota[f]]]
    return sorted(chosen, key=lambda m: (m.path, m.line, m.start, m.kind))


def read_equivalents(path):
    """Lines 'file:line | before -> after | reason'; '#' starts a comment line."""
    entries = []
    if not path or not os.path.exists(path):
        return entries
    with open(path, encoding="utf-8") as f:
        for number, raw in enumerate(f, 1):
            line = raw.strip()
            if not line or line.startswith("#"):
                continue
            parts = line.split(" | ")
            if len(parts) < 3:
                sys.exit(f"{path}:{number}: expected 'file:line | before -> after | reason'")
            where, reason = parts[0].strip(), parts[-1].strip()
            mutation = " ".join(" | ".join(parts[1:-1]).split())
            file, _, lineno = where.rpartition(":")
            if not file or not lineno.isdigit():
                sys.exit(f"{path}:{number}: '{where}' is not file:line")
            entries.append((file, int(lineno), mutation, reason))
    return entries


def match_equivalents(mutants, all_mutants, entries):
    """{mutant id: reason}: an entry matches its file, line and mutation; if the line moved, a
    mutation that occurs once in the file still matches."""
    found = {}
    for file, lineno, mutation, reason in entries:
        same = [m for m in all_mutants if m.path == file and m.mutation == mutation]
        exact = [m for m in same if m.line == lineno]
        hits = exact or (same if len(same) == 1 else [])
        for m in hits:
            found[m.id] = reason if exact else f"{reason} (listed at line {lineno})"
    return {m.id: found[m.id] for m in mutants if m.id in found}


# ----------------------------------------------------------------------------------------------
# The scratch tree and its build.

def git(repo, *args, binary=False):
    out = subprocess.run(["git", "-C", repo, *args], check=True, stdout=subprocess.PIPE)
    return out.stdout if binary else out.stdout.decode().strip()


def head_files(repo):
    """{path: (bytes, mode or symlink target)} of the committed HEAD (git archive: read-only)."""
    data = git(repo, "archive", "--format=tar", "HEAD", binary=True)
    files = {}
    with tarfile.open(fileobj=io.BytesIO(data)) as tar:
        for member in tar.getmembers():
            if member.isfile():
                files[member.name] = (tar.extractfile(member).read(), member.mode)
            elif member.issym():
                files[member.name] = (None, member.linkname)
    return files


def sync_tree(files, tree):
    """Makes tree hold exactly files, rewriting only what differs (fresh mtimes, so the build
    sees every change and nothing else)."""
    changed = 0
    for name, (content, mode) in files.items():
        dest = os.path.join(tree, name)
        os.makedirs(os.path.dirname(dest), exist_ok=True)
        if content is None:
            if not (os.path.islink(dest) and os.readlink(dest) == mode):
                if os.path.lexists(dest):
                    os.remove(dest)
                os.symlink(mode, dest)
                changed += 1
            continue
        if os.path.islink(dest):
            os.remove(dest)
        if os.path.isfile(dest):
            with open(dest, "rb") as f:
                if f.read() == content:
                    continue
        with open(dest, "wb") as f:
            f.write(content)
        os.chmod(dest, mode & 0o777)
        changed += 1
    for root, dirs, names in os.walk(tree, topdown=False):
        for name in names:
            rel = os.path.relpath(os.path.join(root, name), tree)
            if rel not in files:
                os.remove(os.path.join(root, name))
                changed += 1
        for d in dirs:
            full = os.path.join(root, d)
            if not os.path.islink(full) and not os.listdir(full):
                os.rmdir(full)
    return changed


def nice(cmd):
    return ["nice", "-n", "10", *cmd]


def run_logged(cmd, log, cwd=None, env=None, timeout=None):
    """Runs cmd with its output appended to log; returns (exit code or None on timeout, seconds,
    output)."""
    t0 = time.monotonic()
    try:
        p = subprocess.run(cmd, cwd=cwd, env=env, stdout=subprocess.PIPE,
                           stderr=subprocess.STDOUT, timeout=timeout)
        code, out = p.returncode, p.stdout.decode(errors="replace")
    except subprocess.TimeoutExpired as e:
        code, out = None, (e.stdout or b"").decode(errors="replace")
    seconds = time.monotonic() - t0
    with open(log, "a", encoding="utf-8") as f:
        f.write(f"$ {' '.join(cmd)}\n{out}\n[exit {code}, {seconds:.0f} s]\n")
    return code, seconds, out


class Build:
    def __init__(self, work, jobs):
        self.tree = os.path.join(work, "src-tree")
        self.dir = os.path.join(work, "build")
        self.jobs = jobs
        self.stop_on_failure = "--stop-on-failure" in subprocess.run(
            ["ctest", "--help"], stdout=subprocess.PIPE).stdout.decode()

    def configure(self, log):
        if os.path.exists(os.path.join(self.dir, "CMakeCache.txt")):
            return True  # ninja re-runs cmake itself when a CMakeLists.txt changes
        code, _, _ = run_logged(["cmake", "-S", self.tree, "-B", self.dir, *CMAKE_FLAGS], log)
        return code == 0

    def build(self, log):
        code, seconds, _ = run_logged(
            nice(["cmake", "--build", self.dir, "-j", str(self.jobs)]), log)
        return code == 0, seconds

    def test(self, log, stop_on_failure):
        cmd = ["ctest", "-j", str(self.jobs), "--timeout", str(TEST_TIMEOUT_S),
               "--no-tests=error", "--output-on-failure"]
        if stop_on_failure and self.stop_on_failure:
            cmd.append("--stop-on-failure")
        env = dict(os.environ, **TEST_ENV)
        code, seconds, out = run_logged(nice(cmd), log, cwd=self.dir, env=env, timeout=4 * 3600)
        return code, seconds, parse_ctest(out)

    def query_outputs(self, node):
        """What ninja builds directly from node (a path as the build names it)."""
        out = subprocess.run(["ninja", "-C", self.dir, "-t", "query", node],
                             stdout=subprocess.PIPE, stderr=subprocess.DEVNULL).stdout.decode()
        lines = out.split("outputs:", 1)[1].splitlines() if "outputs:" in out else []
        return [os.path.join(self.dir, line.strip()) for line in lines if line.strip()]

    def objects(self, source):
        """Object files compiled from source (ninja names sources by their absolute path)."""
        return [o for o in self.query_outputs(os.path.abspath(source)) if o.endswith(".o")]

    def dependents(self, obj):
        """What is linked from obj (the library)."""
        return self.query_outputs(os.path.relpath(obj, self.dir))


TEST_LINE_RE = re.compile(r"Test\s+#\d+: (\S+) .*?\*\*\*(Failed|Timeout|Exception|Not Run)")
FAILED_LIST_RE = re.compile(r"^\s*\d+ - (\S+) \(([^)]*)\)\s*$")


def parse_ctest(out):
    """[(test name, status)] of the failed tests, in the order ctest reported them."""
    failed = []
    for line in out.splitlines():
        m = TEST_LINE_RE.search(line)
        if m and m.group(1) not in [n for n, _ in failed]:
            failed.append((m.group(1), m.group(2)))
    in_list = False
    for line in out.splitlines():
        if line.startswith("The following tests FAILED"):
            in_list = True
            continue
        m = FAILED_LIST_RE.match(line) if in_list else None
        if m and m.group(1) not in [n for n, _ in failed]:
            failed.append((m.group(1), m.group(2)))
    return [(n, s) for n, s in failed if s != "Not Run"] or failed


def run_mutant(build, m, original, log):
    """Applies m in the scratch tree, rebuilds, runs the suite and restores the file. Returns
    (status, detail, build seconds, test seconds)."""
    path = os.path.join(build.tree, m.path)
    stat = os.stat(path)
    objects = [o for o in build.objects(path) if os.path.exists(o)]
    saved = [(o, o + ".mutation-orig") for o in objects]
    linked = [d for o in objects for d in build.dependents(o)]
    for o, b in saved:
        shutil.copy2(o, b)
    with open(log, "w", encoding="utf-8") as f:
        f.write(f"{m.id} {m.where} {m.kind}\n{m.mutation}\n\n")
    try:
        with open(path, "wb") as f:
            f.write(m.apply(original.decode("utf-8")).encode("utf-8"))
        ok, build_s = build.build(log)
        if not ok:
            return "BUILD-FAILED", "", build_s, 0.0
        code, test_s, failed = build.test(log, stop_on_failure=True)
        if code == 0:
            return "SURVIVED", "", build_s, test_s
        if code is None:
            return "TIMEOUT", "whole suite > 4 h", build_s, test_s
        names = ", ".join(n for n, _ in failed[:3]) + (" ..." if len(failed) > 3 else "")
        if any(s == "Timeout" for _, s in failed[:1]):
            return "TIMEOUT", names, build_s, test_s
        return "KILLED", names or f"ctest exit {code}", build_s, test_s
    finally:
        # Restore the source; then, instead of recompiling it in the next build, put back the
        # unmutated objects with the mtime ninja recorded for them (a newer one would make
        # ninja distrust its dependency log and recompile), delete the library linked from the
        # mutant so that it is relinked, and give the source back its old mtime. Until the last
        # step the source is newer than the objects, so an interruption leaves a tree that
        # rebuilds correctly.
        with open(path, "wb") as f:
            f.write(original)
        for d in linked:
            if os.path.lexists(d):
                os.remove(d)
        for o, b in saved:
            recorded = os.stat(o if os.path.exists(o) else b).st_mtime_ns
            os.replace(b, o)
            os.utime(o, ns=(recorded, recorded))
        if saved and linked:
            os.utime(path, ns=(stat.st_atime_ns, stat.st_mtime_ns))


# ----------------------------------------------------------------------------------------------

def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(
        description="Mutation check of rbaa's test suite (not part of CI: ~1-2 min per mutant).")
    ap.add_argument("--count", type=int, default=40, help="mutants to sample (default 40)")
    ap.add_argument("--seed", type=int, default=1, help="sampling seed (default 1)")
    ap.add_argument("--list", action="store_true", help="print the sample and stop")
    ap.add_argument("--all", action="store_true", help="with --list: print every candidate")
    ap.add_argument("--only", default="", help="comma-separated mutant ids to run instead")
    ap.add_argument("--repo", default=None,
                    help="checkout whose committed HEAD is mutated (default: this script's)")
    ap.add_argument("--report", default="mutation_report.txt", help="report file")
    ap.add_argument("--work", default="/tmp/rbaa-mutation",
                    help="scratch tree, build and logs (default /tmp/rbaa-mutation)")
    ap.add_argument("--equivalent", default=None,
                    help="equivalent-mutants file (default scripts/mutation_equivalent.txt)")
    ap.add_argument("--jobs", type=int, default=2, help="build and ctest parallelism (default 2)")
    ap.add_argument("--skip-baseline", action="store_true",
                    help="do not check that the unmutated tree passes the suite first")
    args = ap.parse_args()
    if args.count < 1:
        sys.exit(f"mutation_check.py: --count must be at least 1 (got {args.count})")
    if args.jobs < 1:
        sys.exit(f"mutation_check.py: --jobs must be at least 1 (got {args.jobs})")
    report_dir = os.path.dirname(os.path.abspath(args.report))
    if not os.path.isdir(report_dir):
        sys.exit(f"mutation_check.py: --report {args.report}: no folder {report_dir}")

    repo = git(args.repo or here, "rev-parse", "--show-toplevel")
    commit = git(repo, "rev-parse", "HEAD")
    files = head_files(repo)
    sources = sorted(p for p in files if files[p][0] is not None and
                     re.fullmatch(r"src/(%s)/[^/]+\.cpp" % "|".join(MODULES), p))
    texts = {p: files[p][0].decode("utf-8") for p in sources}
    all_mutants = [m for p in sources for m in enumerate_file(p, texts[p])]
    if args.only:
        ids = [s.strip() for s in args.only.split(",") if s.strip()]
        chosen = [m for m in all_mutants if m.id in ids]
        missing = set(ids) - {m.id for m in chosen}
        if missing:
            sys.exit(f"no such mutant at {commit[:10]}: {', '.join(sorted(missing))}")
    else:
        chosen = sample(all_mutants, args.count, args.seed)
    eq_file = args.equivalent or next(
        (p for p in (os.path.join(repo, "scripts", "mutation_equivalent.txt"),
                     os.path.join(here, "mutation_equivalent.txt")) if os.path.exists(p)), None)
    equivalent = match_equivalents(chosen, all_mutants, read_equivalents(eq_file))

    per_folder = collections.Counter(m.folder for m in all_mutants)
    per_kind = collections.Counter(m.kind for m in all_mutants)
    header = [
        f"rbaa mutation check: {repo} at {commit[:12]}, seed {args.seed}, "
        f"{len(chosen)} of {len(all_mutants)} candidates",
        "candidates per folder: " + ", ".join(f"{f} {per_folder[f]}" for f in MODULES),
        "candidates per kind: " + ", ".join(f"{k} {n}" for k, n in sorted(per_kind.items())),
        f"equivalent-mutants file: {eq_file or '(none)'}",
    ]

    if args.list:
        print("\n".join(header))
        for m in (sorted(all_mutants, key=lambda m: (m.path, m.line, m.start)) if args.all
                  else chosen):
            note = f"  EQUIVALENT ({equivalent[m.id]})" if m.id in equivalent else ""
            print(f"{m.id}  {m.where}  {m.kind}  {m.mutation}{note}")
        return 0

    os.makedirs(args.work, exist_ok=True)
    lock = open(os.path.join(args.work, "lock"), "w")
    try:
        fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        sys.exit(f"another mutation check is using {args.work}")
    logs = os.path.join(args.work, "logs")
    os.makedirs(logs, exist_ok=True)
    report = open(args.report, "w", encoding="utf-8")

    def say(line=""):
        print(line, flush=True)
        report.write(line + "\n")
        report.flush()

    for line in header:
        say(line)
    build = Build(args.work, args.jobs)
    t0 = time.monotonic()
    changed = sync_tree(files, build.tree)
    setup_log = os.path.join(logs, "setup.log")
    open(setup_log, "w").close()
    if not build.configure(setup_log):
        sys.exit(f"cmake configure failed: see {setup_log}")
    ok, seconds = build.build(setup_log)
    if not ok:
        sys.exit(f"the unmutated tree does not build: see {setup_log}")
    say(f"scratch tree {build.tree} ({changed} files updated), build {build.dir}: "
        f"{seconds:.0f} s")
    stamp = os.path.join(args.work, "baseline-passed")
    if not args.skip_baseline:
        if os.path.exists(stamp) and open(stamp).read().split()[:1] == [commit]:
            say(f"baseline: the suite passed at {commit[:12]} before "
                f"({open(stamp).read().split()[1]} s)")
        else:
            code, seconds, failed = build.test(setup_log, stop_on_failure=False)
            if code != 0:
                names = ", ".join(n for n, _ in failed) or f"ctest exit {code}"
                sys.exit(f"the unmutated tree fails the suite ({names}): see {setup_log}")
            with open(stamp, "w") as f:
                f.write(f"{commit} {seconds:.0f}\n")
            say(f"baseline: the suite passes on the unmutated tree ({seconds:.0f} s)")
    say()

    results = []
    for i, m in enumerate(chosen, 1):
        tag = f"[{i:>{len(str(len(chosen)))}}/{len(chosen)}] {m.id} {m.where} {m.kind}: " \
              f"{m.mutation}"
        if m.id in equivalent:
            results.append((m, "EQUIVALENT", equivalent[m.id]))
            say(f"{tag}  EQUIVALENT ({equivalent[m.id]})")
            continue
        status, detail, build_s, test_s = run_mutant(
            build, m, files[m.path][0], os.path.join(logs, f"{m.id}.log"))
        results.append((m, status, detail))
        times = f"build {build_s:.0f} s" + (f", tests {test_s:.0f} s" if test_s else "")
        say(f"{tag}  {status}{f' ({detail})' if detail else ''}  [{times}]")
    # Leave the build matching the unmutated tree.
    build.build(setup_log)

    counts = collections.Counter(s for _, s, _ in results)
    killed = counts["KILLED"] + counts["TIMEOUT"]
    scored = killed + counts["SURVIVED"]
    say()
    say(f"killed {counts['KILLED']}, timeout {counts['TIMEOUT']}, survived {counts['SURVIVED']}, "
        f"build failed {counts['BUILD-FAILED']} (not scored), equivalent {counts['EQUIVALENT']} "
        f"(not scored)")
    if scored:
        say(f"mutation score: {killed}/{scored} = {100.0 * killed / scored:.0f} % "
            f"(killed / non-equivalent compiled mutants)")
    else:
        say("mutation score: no scored mutants")
    for m, status, detail in results:
        if status == "EQUIVALENT":
            say(f"  equivalent: {m.where} | {m.mutation} | {detail}")
    survivors = [m for m, s, _ in results if s == "SURVIVED"]
    say(f"survivors ({len(survivors)}):")
    for m in survivors:
        say(f"  {m.id} {m.kind:<10} {m.where} | {m.mutation}")
    say(f"total time {(time.monotonic() - t0) / 60:.1f} min; logs in {logs}")
    report.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
