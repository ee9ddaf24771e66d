#!/usr/bin/python3
"""docs_check.py - the manual's links resolve and its pages keep their length limits.

    /usr/bin/python3 tests/docs_check.py SOURCE_DIR

Checks README.md, every docs/*.md and bench/README.md: each relative Markdown link or image
([text](path), ![alt](path), with an optional #anchor) names a file or directory that exists,
and an anchor into a Markdown file names one of its headings (GitHub's slugs); README.md has at
most 250 lines and a command block within its first 40; every docs page at most 500 lines; the
design page opens with "Questions this manual answers"; the project's files name no numbered
stretches of work ("session N"). Prints one line per problem; exit 0 all good, 1 otherwise.
"""
import os
import re
import subprocess
import sys

LINK = re.compile(r'!?\[[^\]]*\]\(([^)\s]+)(?:\s+"[^"]*")?\)')
FENCE = re.compile(r'^\s*(```|~~~)')


def slug(heading):
    """GitHub's anchor for a heading: lower case, punctuation dropped, spaces to hyphens."""
    s = heading.strip().lower()
    s = re.sub(r'[`*_]', '', s)
    s = re.sub(r'[^\w\- ]', '', s)
    return s.replace(' ', '-')


def anchors(path):
    out, seen, fenced = set(), {}, False
    with open(path, encoding='utf-8') as f:
        for line in f:
            if FENCE.match(line):
                fenced = not fenced
                continue
            m = None if fenced else re.match(r'^(#{1,6})\s+(.*?)\s*#*\s*$', line)
            if m:
                base = slug(m.group(2))
                n = seen.get(base, 0)
                seen[base] = n + 1
                out.add(base if n == 0 else '%s-%d' % (base, n))
    return out


def links(path):
    """(line number, target) of every link outside code blocks and inline code."""
    fenced = False
    with open(path, encoding='utf-8') as f:
        for no, line in enumerate(f, 1):
            if FENCE.match(line):
                fenced = not fenced
                continue
            if fenced:
                continue
            for m in LINK.finditer(re.sub(r'`[^`]*`', '', line)):
                yield no, m.group(1)


def main(root):
    problems = []
    docs = os.path.join(root, 'docs')
    pages = [os.path.join(root, 'README.md'), os.path.join(root, 'bench', 'README.md')]
    pages += sorted(os.path.join(docs, p) for p in os.listdir(docs) if p.endswith('.md'))
    for page in pages:
        rel = os.path.relpath(page, root)
        for no, target in links(page):
            if re.match(r'^[a-z][a-z0-9+.-]*:', target):  # http:, https:, mailto:
                continue
            file_part, _, anchor = target.partition('#')
            dest = os.path.normpath(os.path.join(os.path.dirname(page), file_part)) if file_part else page
            if not os.path.exists(dest):
                problems.append('%s:%d: link to %s: no such file' % (rel, no, target))
            elif anchor and dest.endswith('.md') and anchor not in anchors(dest):
                problems.append('%s:%d: link to %s: no heading with that anchor' % (rel, no, target))
        with open(page, encoding='utf-8') as f:
            lines = f.read().split('\n')
        if lines and lines[-1] == '':
            lines.pop()
        limit = 250 if rel == 'README.md' else 500
        if len(lines) > limit:
            problems.append('%s: %d lines, more than %d' % (rel, len(lines), limit))
        if rel == 'README.md' and not any(FENCE.match(l) for l in lines[:40]):
            problems.append('README.md: no command block within the first 40 lines')
    design = os.path.join(docs, 'design.md')
    if os.path.exists(design):
        with open(design, encoding='utf-8') as f:
            heads = [l for l in f if l.startswith('## ')]
        if not heads or heads[0].strip() != '## Questions this manual answers':
            problems.append('docs/design.md: does not open with "Questions this manual answers"')
    else:
        problems.append('docs/design.md: missing')
    if os.path.isdir(os.path.join(root, '.git')) or os.path.isfile(os.path.join(root, '.git')):
        r = subprocess.run(['git', '-C', root, 'grep', '-nIiE', r'session[ -]?[0-9]+'],
                           stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
        for hit in r.stdout.splitlines():
            problems.append('numbered stretch of work: ' + hit[:200])
    for p in problems:
        print('docs: ' + p)
    print('docs: %d pages checked, %d problems' % (len(pages), len(problems)))
    return 1 if problems else 0


if __name__ == '__main__':
    if len(sys.argv) != 2:
        print('usage: docs_check.py SOURCE_DIR', file=sys.stderr)
        sys.exit(2)
    sys.exit(main(sys.argv[1]))
