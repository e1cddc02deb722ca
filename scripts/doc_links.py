#!/usr/bin/env python3
"""Check that every relative link in README.md and docs/ resolves: the file
exists and, for a `#heading` into a markdown file, that heading does
(GitHub's anchor rule: lower case, punctuation dropped, spaces to dashes).
Links inside fenced code blocks are not links. Prints each broken link as
`file:line: target: why` and exits 1 if there is one.

    python3 scripts/doc_links.py
"""

import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
FENCE = re.compile(r"```.*?```", re.S)
LINK = re.compile(r"\[[^\]]*\]\(([^)\s]+)\)")


def without_code(text):
    """The text with fenced blocks blanked, line breaks kept."""
    return FENCE.sub(lambda m: re.sub(r"[^\n]", " ", m.group(0)), text)


def anchors(md):
    heads = re.findall(r"^#+\s+(.*)$", without_code(md.read_text()), re.M)
    return {re.sub(r"[^\w\- ]", "", h.strip().lower()).replace(" ", "-") for h in heads}


def main():
    files = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]
    checked, broken = 0, 0
    for f in files:
        text = without_code(f.read_text())
        for m in LINK.finditer(text):
            target = m.group(1)
            if re.match(r"[a-z][a-z0-9+.-]*:", target):
                continue  # a URL or mailto:
            checked += 1
            path, _, anchor = target.partition("#")
            dest = (f.parent / path).resolve() if path else f
            line = text.count("\n", 0, m.start()) + 1
            where = f"{f.relative_to(ROOT)}:{line}: {target}"
            if not dest.exists():
                print(f"{where}: no such file")
                broken += 1
            elif anchor and dest.suffix == ".md" and anchor not in anchors(dest):
                print(f"{where}: no heading #{anchor}")
                broken += 1
    print(f"{checked} relative links, {broken} broken")
    return 1 if broken else 0


if __name__ == "__main__":
    sys.exit(main())
