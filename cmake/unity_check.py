#!/usr/bin/env python3
"""Finds what a unity batch would share between its files (cmake/MbstreamUnity.cmake).

A batch is one translation unit that includes several .cc files, so what one file declares at
namespace scope with internal linkage (an anonymous namespace, `static`, a const or constexpr
variable), its using-directives and declarations, and its macros are seen by the files after it.
A name that two files of a batch both declare that way is either a compile error (the same
signature: "redefinition of ...") or, worse, an overload set the files never had alone (a call
may then pick the other file's helper, and behaviour changes without a word). Both are found here,
before anything is compiled, and the build stops with the names, the files and the fix.

Usage: unity_check.py SOURCE_ROOT STAMP BATCH.cc...   (exit status 1 when a batch shares a name)
       unity_check.py --files SOURCE_ROOT FILE.cc...  (the files as one batch: tests, by hand)

The parser is deliberately small: comments and literals are blanked, then braces, parentheses and
semicolons are followed at namespace scope. It reads every declaration there, which can only
make it cautious (a name reported that would not have clashed costs one line in
cmake/unity_alone.txt or a rename), never blind to an anonymous-namespace helper.
"""

import os
import re
import sys

IDENT = re.compile(r"[A-Za-z_]\w*")
SKIP_WORDS = {
    "const", "constexpr", "static", "inline", "extern", "volatile", "thread_local", "mutable",
    "unsigned", "signed", "long", "short", "int", "char", "double", "float", "bool", "void",
    "auto", "struct", "class", "union", "enum", "typename", "template", "noexcept", "override",
    "final", "consteval", "constinit", "explicit", "virtual", "friend", "decltype",
}


def blank_comments_and_literals(text):
    """Comments and string/char literals become spaces; newlines stay (line numbers hold)."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c == "R" and text.startswith('R"', i) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            m = re.match(r'R"([^(\s]*)\(', text[i:])
            if not m:
                out.append(c)
                i += 1
                continue
            end = ")" + m.group(1) + '"'
            j = text.find(end, i + m.end())
            j = n if j < 0 else j + len(end)
            out.append('""' + re.sub(r"[^\n]", " ", text[i + 2:j]))
            i = j
        elif c in "\"'":
            if c == "'" and i > 0 and text[i - 1].isalnum():  # a digit separator: 1'000
                out.append(" ")
                i += 1
                continue
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            j = min(j + 1, n)
            out.append(c + " " * (j - i - 2) + c if j - i >= 2 else c)
            i = j
        else:
            out.append(c)
            i += 1
    return "".join(out)


class Record:
    def __init__(self, path, line, namespace, name, kind, internal, target):
        self.path, self.line, self.namespace = path, line, namespace
        self.name, self.kind, self.internal = name, kind, internal
        self.target = target  # what an alias or a using-declaration names
        self.anonymous = False


# Kinds that only name something declared elsewhere: the same one in two files is harmless.
NAMING = ("alias", "namespace-alias", "using-declaration")


def strip_templates(stmt):
    """Drops leading `template <...>` clauses and attributes."""
    while True:
        stmt = stmt.lstrip()
        if stmt.startswith("[["):
            end = stmt.find("]]")
            stmt = stmt[end + 2:] if end >= 0 else ""
            continue
        m = re.match(r"template\s*<", stmt)
        if not m:
            return stmt
        depth, i = 1, m.end()
        while i < len(stmt) and depth:
            depth += {"<": 1, ">": -1}.get(stmt[i], 0)
            i += 1
        stmt = stmt[i:]


def top_level_index(stmt, chars):
    """The first of CHARS outside parentheses, brackets and template arguments, or -1."""
    depth = 0
    for i, c in enumerate(stmt):
        if c in "([":
            if depth == 0 and c in chars:
                return i
            depth += 1
        elif c in ")]":
            depth -= 1
        elif c == "<" and not stmt.startswith("<<", i) and not stmt[max(0, i - 8):i].endswith("operator"):
            depth += 1
        elif c == ">" and not stmt.startswith(">>", i) and stmt[i - 1:i] != "-" and depth > 0:
            depth -= 1
        elif depth == 0 and c in chars:
            return i
    return -1


def declared_name(stmt, with_body):
    """(name, kind, internal-by-keyword, target) of a namespace-scope declaration, or None."""
    found = declared(stmt, with_body)
    if found is None:
        return None
    return found + (None,) * (4 - len(found))


def declared(stmt, with_body):
    stmt = strip_templates(" ".join(stmt.split()))
    if not stmt or stmt.startswith(("static_assert", "extern ", "friend ")):
        return None
    m = re.match(r"(MATCHER\w*|ACTION\w*)\s*\(\s*(\w+)", stmt)
    if m:
        return m.group(2), "matcher", True
    if re.match(r"[A-Z][A-Z0-9_]*\s*\(", stmt):  # TEST(...), INSTANTIATE_TEST_SUITE_P(...)
        return None
    m = re.match(r"using\s+namespace\s+([\w:]+)", stmt)
    if m:
        return m.group(1), "using-directive", True, m.group(1).lstrip(":")
    m = re.match(r"namespace\s+(\w+)\s*=\s*([\w:]+)$", stmt)
    if m:
        return m.group(1), "namespace-alias", True, m.group(2).lstrip(":")
    m = re.match(r"using\s+(\w+)\s*=\s*(.*)$", stmt)
    if m:
        return m.group(1), "alias", False, m.group(2).replace(" ", "").lstrip(":")
    m = re.match(r"using\s+(?:typename\s+)?([\w:]+)$", stmt)
    if m:
        return m.group(1).split("::")[-1], "using-declaration", True, m.group(1).lstrip(":")
    if stmt.startswith("typedef "):
        names = IDENT.findall(stmt)
        return (names[-1], "alias", False, stmt) if names else None
    static = bool(re.match(r"(?:(?:inline|constexpr|const)\s+)*static\b", stmt))
    m = re.match(r"(?:(?:static|inline|constexpr)\s+)*(struct|class|union|enum(?:\s+class|\s+struct)?)\s+"
                 r"(?:\[\[[^\]]*\]\]\s*)?(\w+)\s*(?:final\s*)?(:[^{]*)?$", stmt)
    if m:
        return (m.group(2), "type", False) if with_body else None
    paren = top_level_index(stmt, "(=")
    if paren >= 0 and stmt[paren] == "(":
        head = stmt[:paren].rstrip()
        if not head or "operator" in head.split()[-1] or "::" in head.split()[-1]:
            return None
        names = IDENT.findall(head)
        if not names or names[-1] in SKIP_WORDS:
            return None
        return names[-1], "function", static
    end = top_level_index(stmt, "=[{")
    head = stmt if end < 0 else stmt[:end]
    names = [n for n in IDENT.findall(head) if n not in SKIP_WORDS]
    if not names or "::" in head.split()[-1]:
        return None
    constant = re.search(r"\b(const|constexpr)\b", head) and not re.search(r"\binline\b", head)
    return names[-1], "variable", static or bool(constant)


def parse(path, root):
    """The namespace-scope records and the leaking macros of one file."""
    with open(os.path.join(root, path), encoding="utf-8", errors="replace") as f:
        raw = f.read()
    text = blank_comments_and_literals(raw)
    macros = []  # (name, line) defined and not undefined again
    lines = text.split("\n")
    defined = {}
    in_directive = False
    for number, line in enumerate(lines):
        stripped = line.strip()
        if in_directive or stripped.startswith("#"):
            m = re.match(r"#\s*define\s+(\w+)", stripped)
            if m and not in_directive:
                defined[m.group(1)] = number + 1
            m = re.match(r"#\s*undef\s+(\w+)", stripped)
            if m and not in_directive:
                defined.pop(m.group(1), None)
            in_directive = line.rstrip().endswith("\\")
            lines[number] = " " * len(line)
    macros = sorted(defined.items(), key=lambda item: item[1])
    text = "\n".join(lines)

    records = []
    # Scope stack: ("ns", name) with "" for an anonymous one, ("extern",), ("class",),
    # ("block",): only declarations directly in a namespace are read.
    stack = []
    stmt_start = 0
    paren = 0
    tail = False  # after a class body or a braced initializer: skip to its ';'
    pstack = []  # braces inside parentheses at namespace scope (default arguments)
    for m in re.finditer(r"[{}();]", text):
        c, pos = m.group(), m.start()
        at_namespace = all(s[0] in ("ns", "extern") for s in stack) and not pstack
        if not at_namespace:
            if c == "{":
                stack.append(("block",))
            elif c == "}" and stack:
                kind = stack.pop()
                if kind[0] == "pbrace":
                    pstack.pop()
                elif all(s[0] in ("ns", "extern") for s in stack) and not pstack:
                    tail = kind[0] in ("class", "init")
                    stmt_start, paren = pos + 1, 0
            continue
        if c == "(":
            paren += 1
            continue
        if c == ")":
            paren = max(0, paren - 1)
            continue
        stmt = text[stmt_start:pos]
        line = text.count("\n", 0, stmt_start + len(stmt) - len(stmt.lstrip())) + 1
        namespace = [s[1] for s in stack if s[0] == "ns"]
        if c == "{" and paren > 0:
            stack.append(("pbrace",))
            pstack.append(True)
            continue
        if c == "}":
            if stack:
                stack.pop()
            stmt_start, paren, tail = pos + 1, 0, False
            continue
        if tail:
            if c == ";":
                tail = False
                stmt_start, paren = pos + 1, 0
            else:
                stack.append(("block",))
            continue
        flat = " ".join(stmt.split())
        if c == "{":
            ns = re.fullmatch(r"(?:inline\s+)?namespace\s*([\w:]*)(?:\s*\[\[.*\]\])?", flat)
            if ns:
                names = ns.group(1).split("::") if ns.group(1) else [""]
                for name in names:
                    stack.append(("ns", name))
                # One entry per component; a '}' closes them all.
                if len(names) > 1:
                    stack[-len(names):] = [("ns", "::".join(names))]
                stmt_start, paren = pos + 1, 0
                continue
            if re.fullmatch(r'extern\s*""', flat):
                stack.append(("extern",))
                stmt_start, paren = pos + 1, 0
                continue
            found = declared_name(stmt, with_body=True)
            body = "block"
            if found:
                body = "class" if found[1] == "type" else ("block" if found[1] == "function" or found[1] == "matcher" else "init")
            elif re.match(r"\s*(?:template\s*<.*>\s*)?(?:struct|class|union|enum)\b", stmt, re.S):
                body = "class"
            elif top_level_index(" ".join(stmt.split()), "(") < 0:
                body = "init"
            stack.append((body,))
        else:
            found = declared_name(stmt, with_body=False)
        stmt_start, paren = pos + 1, 0
        if found:
            name, kind, internal, target = found
            anonymous = "" in namespace
            records.append(Record(path, line, "::".join(n for n in namespace if n), name, kind,
                                  internal or anonymous, target))
            records[-1].anonymous = anonymous
            records[-1].definition = c == "{"
    # Names used as such (not after '.', '->' or '::': members and qualified names are looked
    # up elsewhere).
    used = set(m.group(1) for m in re.finditer(r"(?<![\w.:>])(?<!->)\s*([A-Za-z_]\w*)", text))
    return records, macros, used


def check_batch(label, files, root):
    """Messages for what the files of one batch would share."""
    problems = []
    seen = {}  # (namespace, name) -> records
    parsed = [(path, *parse(path, root)) for path in files]
    for path, records, _, _ in parsed:
        for record in records:
            seen.setdefault((record.namespace, record.name), []).append(record)
    for (namespace, name), records in sorted(seen.items()):
        files_of = {r.path for r in records}
        if len(files_of) < 2:
            continue
        if all(r.kind == "using-directive" for r in records):
            continue  # directives: below
        if all(r.kind in NAMING for r in records):
            if len({(r.kind, r.target) for r in records}) == 1:
                continue  # the same alias or using-declaration twice changes nothing
        elif not any(r.internal for r in records):
            continue  # declarations of one external name (defined once, or a link error)
        where = ", ".join(f"{r.path}:{r.line} ({r.kind})" for r in records)
        scope = namespace or "the global namespace"
        problems.append(f"'{name}' in {scope} is declared by more than one file of {label}: {where}")
    # A function defined in a namespace and one of the same name defined in a namespace inside
    # it: calls in the inner one also find the outer one by argument-dependent lookup (and calls
    # that name the outer one's namespace find it), so a file that did not see the other's
    # declaration alone may pick a different overload in the batch.
    defined = {}
    for path, records, _, _ in parsed:
        for r in records:
            if r.kind == "function" and r.definition:
                defined.setdefault(r.name, []).append(r)
    for name, records in sorted(defined.items()):
        for a in records:
            for b in records:
                if a.path < b.path and a.namespace != b.namespace and (
                        a.namespace.startswith(b.namespace + "::") or b.namespace.startswith(a.namespace + "::")
                        or not a.namespace or not b.namespace):
                    problems.append(f"function '{name}' is defined in {a.namespace or 'the global namespace'} "
                                    f"({a.path}:{a.line}) and in {b.namespace or 'the global namespace'} "
                                    f"({b.path}:{b.line}), one inside the other, in {label}: a call may find both")
    # A function or type a file declares with internal linkage hides, or joins the overloads of,
    # what a later file means by that name (from one of its headers).
    for index, (path, records, _, _) in enumerate(parsed):
        for r in records:
            if not r.internal or r.kind not in ("function", "type", "matcher"):
                continue
            for later, later_records, _, used in parsed[index + 1:]:
                if r.name in used and not any(x.name == r.name for x in later_records):
                    problems.append(f"'{r.name}' ({r.kind}, {path}:{r.line}) is also a name that {later}, "
                                    f"after it in {label}, uses: there it would find this one too")
    # A using-directive at namespace scope makes a namespace's names visible to the files after
    # it: names those files declare may then clash or overload with them.
    # The same directive in the same namespace of every later file changes nothing.
    def directives(records):
        return {(r.namespace, r.target) for r in records if r.kind == "using-directive"}

    for index, (path, records, _, _) in enumerate(parsed):
        for record in records:
            if record.kind != "using-directive":
                continue
            lacking = [p for p, other, *_ in parsed[index + 1:]
                       if (record.namespace, record.target) not in directives(other)]
            if lacking:
                later = ", ".join(lacking)
                problems.append(f"'using namespace {record.name};' at namespace scope in {path}:{record.line} "
                                f"reaches the files after it in {label} ({later}); "
                                "move it into the functions that need it")
    # A macro a file defines (and does not #undef) reaches the files after it.
    for index, (path, _, macros, _) in enumerate(parsed):
        for name, line in macros:
            users = [p for p, _, other_macros, idents in parsed[index + 1:]
                     if name in idents or any(n == name for n, _ in other_macros)]
            if users:
                problems.append(f"macro {name} defined in {path}:{line} reaches {', '.join(users)} in {label}; "
                                f"#undef it at the end of {path}")
    return problems


def batch_files(batch):
    with open(batch, encoding="utf-8") as f:
        return re.findall(r'^#include "([^"]+)"', f.read(), re.M)


def main(argv):
    if len(argv) >= 3 and argv[1] == "--files":
        root, files = argv[2], argv[3:]
        problems = check_batch("the batch", files, root)
        stamp = None
    elif len(argv) >= 3:
        root, stamp, batches = argv[1], argv[2], argv[3:]
        problems = []
        for batch in batches:
            label = "batch " + os.path.relpath(batch, os.path.dirname(os.path.dirname(os.path.dirname(batch))))
            problems += check_batch(label, batch_files(batch), root)
    else:
        sys.stderr.write(__doc__)
        return 2
    if problems:
        sys.stderr.write("unity_check: files of one unity batch would share names (cmake/MbstreamUnity.cmake):\n")
        for problem in problems:
            sys.stderr.write("  " + problem + "\n")
        sys.stderr.write(
            "Fix: rename the helper in one of the files (a name of its own), or compile one file on its\n"
            "own: add its path to cmake/unity_alone.txt with a comment naming the clash, e.g.\n"
            "  server/x/new_file.cc   # Seconds (replay_grid.cc)\n"
            "(docs/contributing.md, \"Unity builds\").\n")
        return 1
    if stamp:
        with open(stamp, "w", encoding="utf-8") as f:
            f.write("ok\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
