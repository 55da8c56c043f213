#!/usr/bin/env python3
"""Wraps help text (stdin) to a width (argv[1], default 72) for the man page's no-fill blocks: a long
line breaks at spaces, its continuation indented to the line's description column (the text after the
first run of two or more spaces), else to the line's own indentation. Words are never split."""
import re
import sys
import textwrap

width = int(sys.argv[1]) if len(sys.argv) > 1 else 72
for line in sys.stdin.read().split("\n"):
    if len(line) <= width:
        print(line)
        continue
    column = re.match(r"^(\s*\S.*?\s{2,})\S", line)
    indent = len(column.group(1)) if column and len(column.group(1)) < width // 2 else len(line) - len(line.lstrip())
    first = len(line) - len(line.lstrip())
    print("\n".join(textwrap.wrap(line.strip(), width=width, initial_indent=" " * first,
                                  subsequent_indent=" " * indent, break_long_words=False,
                                  break_on_hyphens=False)))
