#!/usr/bin/env python3
"""Static verification of the real-time tasks' period functions (docs/verification.md).

Reads the call graph GCC writes with -fcallgraph-info=su (one .ci file per translation unit, the
`verify` preset), merges it into one program graph and, for each real-time task's period function
named in the configuration (toolchain/rt-verify.json):

  stack      prints the deepest stack path with its bytes (frame sizes from GCC, an assumed size per
             call into code GCC did not compile, e.g. libc) and fails when it exceeds the stack each
             task prefaults at start-up (hal::kTaskStackPrefaultBytes, read from hal/rt/rt_setup.hpp);
             recursion and dynamically sized frames are reported and fail.
  blocking   fails when a path reaches a denied symbol (allocation, locks, blocking system calls,
             stdio, ...), or an external symbol the configuration does not classify, unless an
             allow-list entry with its reason covers that call.

Indirect calls (GCC's `__indirect_call` placeholder) are resolved soundly: the callee's name is read
from the source at the call's location; a call through a member (virtual) resolves to every function
of the graph with that method name; a call listed in the configuration's `indirect` table resolves to
the targets listed there; anything else is an unresolved indirect call, reported, and fails.

Output: `key: value unit` lines and the paths; exit status 0 when every check passes, 1 otherwise,
2 on a usage error.
"""
import argparse
import collections
import glob
import json
import os
import re
import subprocess
import sys

INDIRECT = "__indirect_call"


class Node:
    __slots__ = ("title", "qname", "signature", "location", "stack", "dynamic", "defined", "tu")

    def __init__(self, title, label, defined, tu):
        self.title = title
        lines = label.split("\\n")
        self.signature = lines[0]
        self.location = lines[1] if len(lines) > 1 else ""
        self.qname = qualified_name(self.signature)
        m = re.match(r"^(.*)\.(part|isra|constprop|cold|lto_priv)\.?\d*$", bare(title))
        if m and not re.match(r"^[A-Za-z_~]", self.qname):
            self.qname = bare(title)  # a GCC clone (f.part.0): its label has no usable name
        if not defined and not bare(title).startswith("_Z"):
            self.qname = bare(title)  # a C function: its label may be unusable (variadic: ")")
        self.stack = 0
        self.dynamic = ""
        self.defined = defined
        self.tu = tu
        if len(lines) > 2:
            m = re.match(r"(\d+) bytes \(([^)]*)\)", lines[2])
            if m:
                self.stack = int(m.group(1))
                if m.group(2) != "static":
                    self.dynamic = m.group(2)


def qualified_name(signature):
    """'virtual bool rescue::A<T>::f(int) const [with T = x]' -> 'rescue::A<T>::f'."""
    sig = re.sub(r"\s*\[with .*\]$", "", signature)
    depth = 0
    i = 0
    while i < len(sig):
        c = sig[i]
        if sig.startswith("operator", i) and (i == 0 or not (sig[i - 1].isalnum() or sig[i - 1] == "_")):
            # operator(), operator<, operator new ...: the name runs to the parameter list.
            end = sig.find("(", i + len("operator") + (2 if sig.startswith("operator()", i) else 0))
            start = sig.rfind(" ", 0, i) + 1
            return sig[start:end].lstrip("*&")
        if c == "<":
            depth += 1
        elif c == ">":
            depth -= 1
        elif c == "(" and depth == 0:
            head = sig[:i]
            # The last space outside template brackets separates the return type.
            d = 0
            cut = -1
            for k, ch in enumerate(head):
                if ch == "<":
                    d += 1
                elif ch == ">":
                    d -= 1
                elif ch == " " and d == 0:
                    cut = k
            name = head[cut + 1:]
            return name.lstrip("*&")
        i += 1
    return sig


def last_component(qname):
    d = 0
    cut = 0
    i = 0
    while i < len(qname):
        ch = qname[i]
        if ch == "<":
            d += 1
        elif ch == ">":
            d -= 1
        elif d == 0 and qname.startswith("::", i):
            cut = i + 2
            i += 1
        i += 1
    name = qname[cut:]
    return re.sub(r"<.*>$", "", name) if not name.startswith("operator") else name


def bare(title):
    return title.rsplit(":", 1)[-1]


NODE_RE = re.compile(r'^node: \{ title: "([^"]*)" label: "((?:[^"\\]|\\.)*)"( shape : ellipse)? \}')
EDGE_RE = re.compile(r'^edge: \{ sourcename: "([^"]*)" targetname: "([^"]*)"(?: label: "([^"]*)")? \}')


class Graph:
    def __init__(self):
        self.nodes = {}          # title -> Node (definitions, and externals by bare name)
        self.by_bare = {}        # bare mangled name -> title of a definition
        self.edges = collections.defaultdict(list)  # title -> [(target title, call location)]
        self.indirect = collections.defaultdict(list)  # title -> [call location]
        self.files = 0
        self.virtuals = None  # mangled names in vtables (None: unknown, every method name counts)

    def load(self, path):
        self.files += 1
        tu = None
        pending = []
        with open(path, encoding="utf-8", errors="replace") as f:
            for line in f:
                if tu is None and line.startswith("graph:"):
                    tu = line.split('"')[1]
                    continue
                m = NODE_RE.match(line)
                if m:
                    title, label, ellipse = m.group(1), m.group(2), bool(m.group(3))
                    if title == INDIRECT:
                        continue
                    node = Node(title, label, not ellipse, tu)
                    if node.defined:
                        self.nodes[title] = node
                        self.by_bare.setdefault(bare(title), title)
                    elif title not in self.nodes:
                        self.nodes[title] = node
                    continue
                m = EDGE_RE.match(line)
                if m:
                    pending.append((m.group(1), m.group(2), m.group(3) or ""))
        for source, target, where in pending:
            if target == INDIRECT:
                self.indirect[source].append(where)
            else:
                self.edges[source].append((target, where))

    def finish(self):
        # An edge to a function another translation unit defines points at that definition.
        for source in list(self.edges):
            self.edges[source] = sorted(set((self.resolve(t), w) for t, w in self.edges[source]))
        for title in list(self.nodes):
            node = self.nodes[title]
            if not node.defined and bare(title) in self.by_bare and self.by_bare[bare(title)] != title:
                del self.nodes[title]

    def resolve(self, title):
        node = self.nodes.get(title)
        if node is not None and node.defined:
            return title
        found = self.by_bare.get(bare(title))
        if found is None:
            # Itanium C++ ABI: a complete-object constructor/destructor (C1/D1) of a class without
            # virtual bases is an alias GCC emits for the base-object one (C2/D2): call sites name
            # C1, the call graph defines only C2.
            base_variant = re.sub(r"([CD])1E", r"\g<1>2E", bare(title), count=1)
            found = self.by_bare.get(base_variant)
        return found if found is not None else title


def virtual_functions(object_files):
    """Mangled names of every function whose address sits in read-only relocated data of the
    objects: the vtables' entries (and constant tables of function pointers)."""
    names = set()
    for chunk in range(0, len(object_files), 64):
        try:
            text = subprocess.run(["readelf", "-rW"] + object_files[chunk:chunk + 64], check=False,
                                  capture_output=True, text=True).stdout
        except OSError:
            return None
        section = ""
        for line in text.splitlines():
            if line.startswith("Relocation section"):
                section = line.split("'")[1]
                continue
            if ".data.rel.ro" not in section:
                continue
            fields = line.split()
            if len(fields) >= 5 and fields[2] == "R_X86_64_64" and fields[4].startswith("_Z"):
                names.add(fields[4])
    return names


def callee_name_at(source_root, build_dir, where):
    """Name of the called expression at 'path:line:col' (GCC points at the call's '(')."""
    m = re.match(r"^(.*):(\d+):(\d+)$", where)
    if not m:
        return None
    path, line, col = m.group(1), int(m.group(2)), int(m.group(3))
    full = os.path.normpath(os.path.join(build_dir, path)) if not os.path.isabs(path) else path
    try:
        with open(full, encoding="utf-8", errors="replace") as f:
            lines = f.readlines()
        text = lines[line - 1]
    except (OSError, IndexError):
        return None
    # GCC points at the call's '(', at its closing ')' or into the called name.
    while col - 1 < len(text) and (text[col - 1].isalnum() or text[col - 1] == "_"):
        col += 1
    if col - 1 < len(text) and text[col - 1] == ")":
        depth = 0
        for k in range(col - 1, -1, -1):
            if text[k] == ")":
                depth += 1
            elif text[k] == "(":
                depth -= 1
                if depth == 0:
                    col = k + 1
                    break
        else:
            return None
    head = text[:col - 1].rstrip()
    # Skip explicit template arguments: obj.f<T>(...).
    if head.endswith(">"):
        depth = 0
        for k in range(len(head) - 1, -1, -1):
            if head[k] == ">":
                depth += 1
            elif head[k] == "<":
                depth -= 1
                if depth == 0:
                    head = head[:k].rstrip()
                    break
    m = re.search(r"([A-Za-z_~][A-Za-z0-9_]*)$", head)
    if not m:
        return None
    name = m.group(1)
    before = head[:m.start()].rstrip()
    member = before.endswith(".") or before.endswith("->")
    # The whole call expression (arguments may hold the indirect call GCC located at the outer call).
    rest = "".join([text[col - 1:]] + lines[line:line + 8])
    depth = 0
    end = len(rest)
    for k, ch in enumerate(rest):
        if ch == "(":
            depth += 1
        elif ch == ")":
            depth -= 1
            if depth == 0:
                end = k
                break
    inner = re.findall(r"(?:\.|->)\s*([A-Za-z_][A-Za-z0-9_]*)\s*\(", rest[:end])
    return name, member, inner


class Checker:
    def __init__(self, graph, config, source_root, build_dir, out):
        self.g = graph
        self.cfg = config
        self.src = source_root
        self.build = build_dir
        self.out = out
        self.deny = [(re.compile(d["symbol"]), d["why"]) for d in config["deny"]]
        self.safe = [re.compile(s["symbol"]) for s in config["safe_externals"]]
        self.allow = config.get("allow", [])
        self.indirect_cfg = config.get("indirect", [])
        self.ext_stack = int(config.get("external_stack_bytes", 0))
        self.boundaries = [(re.compile(b["function"]), b["why"]) for b in config.get("boundaries", [])]
        self.by_method = collections.defaultdict(list)
        for title, node in graph.nodes.items():
            if node.defined and "::" in node.qname and (graph.virtuals is None or bare(title) in graph.virtuals):
                self.by_method[last_component(node.qname)].append(title)
        self.boundaries_hit = collections.defaultdict(set)
        self._succ = {}
        self.unresolved = {}  # (caller title, where) -> text

    def denied(self, node):
        for rx, why in self.deny:
            if rx.fullmatch(node.qname) or rx.fullmatch(bare(node.title)):
                return why
        return None

    def boundary(self, title):
        n = self.node(title)
        name = n.qname if n is not None else title
        for rx, why in self.boundaries:
            if rx.fullmatch(name):
                return why
        return None

    def boundary_reason(self, name):
        for rx, why in self.boundaries:
            if rx.fullmatch(name):
                return why
        return None

    def is_safe_external(self, node):
        return any(rx.fullmatch(node.qname) or rx.fullmatch(bare(node.title)) for rx in self.safe)

    def successors(self, title):
        """[(target title, call location, how)] with indirect calls resolved."""
        if title in self._succ:
            return self._succ[title]
        result = [(t, w, "call") for t, w in self.g.edges.get(title, [])]
        self._succ[title] = result  # (a cycle through inlined copies sees the direct calls only)
        for where in sorted(set(self.g.indirect.get(title, []))):
            found = callee_name_at(self.src, self.build, where)
            if found is None:
                result.append(("<unresolved indirect call ?>", where, "unresolved"))
                continue
            name, member, inner_names = found
            # The called name: configured targets, every virtual of that name, or (a non-virtual
            # member GCC inlined here) the indirect calls of its out-of-line copies.
            resolved = None
            for entry in self.indirect_cfg:
                if entry["name"] == name and re.search(entry.get("file", ""), where):
                    rx = re.compile(entry["signature"])
                    resolved = [(t, "function pointer %s: every function of its type" % name)
                                for t, n in self.g.nodes.items() if n.defined and rx.fullmatch(n.signature)]
                    break
            if resolved is None and member and self.by_method.get(name):
                resolved = [(t, "virtual %s (every method of that name)" % name) for t in self.by_method[name]]
            if resolved is None and member:
                copies = [t for t, n in self.g.nodes.items()
                          if n.defined and last_component(n.qname) == name and t != title]
                inner = [x for c in copies for x in self.successors(c) if x[2] != "call"]
                if copies and all(x[2] != "unresolved" for x in inner):
                    resolved = [(x[0], "indirect call of inlined %s" % name) for x in inner]
            # The arguments' virtual calls (GCC may locate them at the outer call).
            in_args = [(t, "virtual %s in the arguments of %s" % (n, name))
                       for n in inner_names if n != name for t in self.by_method.get(n, [])]
            if resolved is None and not (member and in_args):
                self.unresolved[(title, where)] = name
                result.append(("<unresolved indirect call %s>" % name, where, "unresolved"))
            result += [(t, where, how) for t, how in sorted(set((resolved or []) + in_args))]
        return result

    def node(self, title):
        n = self.g.nodes.get(title)
        return n

    def frame(self, title):
        n = self.node(title)
        if n is None:
            return 0
        if n.defined:
            return n.stack
        return self.ext_stack

    def label(self, title):
        n = self.node(title)
        return n.qname if n is not None else title

    # ---------- stack ----------
    def deepest(self, entry):
        """(bytes, path, recursion cycles, dynamic frames) of the deepest path from entry."""
        memo = {}
        on_path = set()
        cycles = []
        dynamic = set()

        def visit(t):
            if t in memo:
                return memo[t]
            if t in on_path:
                return None
            n = self.node(t)
            if n is not None and n.dynamic:
                dynamic.add((t, n.dynamic))
            on_path.add(t)
            best = (0, [])
            if n is not None and n.defined and self.denied(n) is None and self.boundary(t) is None:
                for s, _w, _how in self.successors(t):
                    if s in on_path:
                        cycles.append((t, s))
                        continue
                    r = visit(s)
                    if r is not None and r[0] > best[0]:
                        best = r
            on_path.discard(t)
            res = (self.frame(t) + best[0], [t] + best[1])
            memo[t] = res
            return res

        total, path = visit(entry)
        return total, path, cycles, dynamic

    # ---------- reachability ----------
    def reach(self, entry, cut):
        """Parent map of a breadth-first search from entry; nodes for which cut(title) is true are
        reached but not expanded."""
        parent = {entry: None}
        queue = collections.deque([entry])
        while queue:
            t = queue.popleft()
            n = self.node(t)
            if n is None or not n.defined or cut(t) or self.boundary(t) is not None:
                continue
            if t != entry and self.denied(n) is not None:
                continue
            for s, w, how in self.successors(t):
                if s not in parent:
                    parent[s] = (t, w, how)
                    queue.append(s)
        return parent

    def path_to(self, parent, t):
        path = []
        while t is not None:
            p = parent[t]
            path.append((t, p[1] if p else "", p[2] if p else ""))
            t = p[0] if p else None
        return list(reversed(path))

    def allow_entries(self, task, sym):
        n = self.node(sym)
        names = {bare(sym), n.qname if n else sym}
        return [a for a in self.allow
                if any(re.fullmatch(a["symbol"], x) for x in names)
                and (not a.get("tasks") or task in a["tasks"])]

    def check_task(self, task, entry):
        failures = 0
        parent = self.reach(entry, lambda t: False)
        findings = []
        for t in parent:
            if t == entry:
                continue
            if t.startswith("<unresolved"):
                findings.append((t, "unresolved indirect call (name the targets in the configuration)"))
                continue
            n = self.node(t)
            if n is None:
                continue
            why = self.denied(n)
            if why is None and not n.defined and not self.is_safe_external(n):
                why = "external symbol not classified (add it to deny or safe_externals)"
            if why is not None:
                findings.append((t, why))
        for name in sorted(set(self.label(t) for t in parent if t != entry and self.boundary(t) is not None)):
            self.out.write("%s_boundary: %s: %s\n" % (task, name, self.boundary_reason(name)))
        allowed = []
        for t, why in sorted(findings, key=lambda x: self.label(x[0])):
            entries = self.allow_entries(task, t) if not t.startswith("<") else []
            if entries:
                vias = [re.compile(a["via"]) for a in entries]
                p2 = self.reach(entry, lambda x: any(v.fullmatch(self.label(x)) for v in vias))
                if t not in p2:
                    allowed.append((t, entries))
                    continue
                path = self.path_to(p2, t)
            else:
                path = self.path_to(parent, t)
            failures += 1
            self.out.write("%s_violation: %s: %s\n" % (task, self.label(t), why))
            for title, where, how in path:
                extra = " [%s]" % how if how and how != "call" else ""
                self.out.write("    %s%s%s\n" % (self.label(title), ("   (called at %s)" % where) if where else "", extra))
        for t, entries in allowed:
            for a in entries:
                kind = "known_finding" if a.get("known_finding") else "allowed"
                self.out.write("%s_%s: %s via %s: %s\n" % (task, kind, self.label(t), a["via"], a["why"]))
        return failures, len(allowed)


def read_stack_limit(source_root, spec):
    path = os.path.join(source_root, spec["file"])
    with open(path, encoding="utf-8") as f:
        text = f.read()
    m = re.search(spec["constant"] + r"\s*=\s*([^;]*);", text)
    if not m:
        raise SystemExit("rt_verify: %s not found in %s" % (spec["constant"], path))
    value = 1
    for number in re.findall(r"\d+", m.group(1)):
        value *= int(number)
    return value


def find_entry(graph, qname):
    matches = [t for t, n in graph.nodes.items() if n.defined and n.qname == qname]
    return matches


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default="build/verify", help="build directory holding the .ci/.su files")
    ap.add_argument("--source", default=".", help="source root (stack-limit constant, call sites)")
    ap.add_argument("--config", default=None, help="configuration (default toolchain/rt-verify.json)")
    ap.add_argument("--stack-limit", type=int, default=None, help="bytes; overrides the configured constant")
    ap.add_argument("--paths", action="store_true", help="print every frame of the deepest stack paths")
    args = ap.parse_args(argv)
    config_path = args.config or os.path.join(args.source, "toolchain", "rt-verify.json")
    with open(config_path, encoding="utf-8") as f:
        config = json.load(f)
    files = sorted(glob.glob(os.path.join(args.build, "**", "*.ci"), recursive=True))
    if not files:
        print("rt_verify: no .ci files under %s (build the `verify` preset first)" % args.build)
        return 2
    graph = Graph()
    for path in files:
        graph.load(path)
    graph.finish()
    objects = sorted(glob.glob(os.path.join(args.build, "**", "*.o"), recursive=True))
    graph.virtuals = virtual_functions(objects) if objects else None
    limit = args.stack_limit if args.stack_limit is not None else read_stack_limit(args.source, config["stack_limit"])
    out = sys.stdout
    checker = Checker(graph, config, os.path.abspath(args.source), os.path.abspath(args.build), out)
    out.write("rt_verify_units: %d files\n" % graph.files)
    out.write("rt_verify_functions: %d functions\n" % sum(1 for n in graph.nodes.values() if n.defined))
    out.write("rt_verify_virtual_functions: %s\n" % (len(graph.virtuals) if graph.virtuals is not None else "unknown (no objects: every method of a called name counts)"))
    out.write("rt_verify_stack_limit: %d bytes\n" % limit)
    out.write("rt_verify_external_frame_assumed: %d bytes\n" % checker.ext_stack)
    failures = 0
    for task in config["tasks"]:
        name = task["name"]
        entries = find_entry(graph, task["entry"])
        if len(entries) != 1:
            out.write("%s_entry: %s: %s\n" % (name, task["entry"], "not found" if not entries else "ambiguous"))
            failures += 1
            continue
        entry = entries[0]
        total, path, cycles, dynamic = checker.deepest(entry)
        out.write("%s_entry: %s\n" % (name, task["entry"]))
        out.write("%s_stack_deepest: %d bytes\n" % (name, total))
        out.write("%s_stack_headroom: %d bytes\n" % (name, limit - total))
        out.write("%s_stack_path_depth: %d calls\n" % (name, len(path)))
        shown = path if args.paths or len(path) <= 12 else path[:6] + [None] + path[-5:]
        for t in shown:
            if t is None:
                out.write("    ...\n")
                continue
            n = checker.node(t)
            kind = "" if n is None or n.defined else " (external, assumed)"
            out.write("    %6d  %s%s\n" % (checker.frame(t), checker.label(t), kind))
        for a, b in cycles:
            out.write("%s_recursion: %s -> %s\n" % (name, checker.label(a), checker.label(b)))
            failures += 1
        # A dynamically sized frame (alloca) fails unless the configuration bounds it with a reason;
        # each bound is added to the deepest path, as if every such frame were on it at once.
        dynamic_extra = 0
        for t, kind in sorted(dynamic):
            if kind == "dynamic,bounded":
                continue
            bound = next((d for d in config.get("dynamic_frames", [])
                          if re.fullmatch(d["function"], checker.label(t))), None)
            if bound is not None:
                out.write("%s_dynamic_frame_bounded: %s (+%d bytes: %s)\n" % (name, checker.label(t), bound["bytes"], bound["why"]))
                dynamic_extra += bound["bytes"]
                continue
            out.write("%s_dynamic_frame: %s (%s)\n" % (name, checker.label(t), kind))
            failures += 1
        if dynamic_extra:
            out.write("%s_stack_deepest_with_dynamic_frames: %d bytes\n" % (name, total + dynamic_extra))
        if total + dynamic_extra > limit:
            out.write("%s_stack_violation: deepest path %d bytes exceeds the prefaulted %d bytes\n" % (name, total + dynamic_extra, limit))
            failures += 1
        f, allowed = checker.check_task(name, entry)
        reached = len(checker.reach(entry, lambda t: False))
        out.write("%s_functions_reached: %d\n" % (name, reached))
        out.write("%s_blocking_violations: %d\n" % (name, f))
        out.write("%s_blocking_allowed: %d\n" % (name, allowed))
        failures += f
    out.write("rt_verify_result: %s\n" % ("pass" if failures == 0 else "FAIL (%d findings)" % failures))
    return 0 if failures == 0 else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
