#!/usr/bin/env python3
"""What sbatch would read of a batch script's #SBATCH lines, as Slurm's src/sbatch/opt.c reads them:
the lines from the top up to the first command (a line that is neither blank nor a comment), split
into arguments where whitespace is outside quotes; ' and " group, a backslash takes the next
character as it is, an unquoted # ends the line. Prints one argument a line, with a line break as
\\n. Usage: sbatch_directives.py SCRIPT"""
import sys

def arguments(text):
    out, i = [], 0
    while True:
        while i < len(text) and text[i].isspace():
            i += 1
        if i == len(text):
            return out
        arg, quote = '', None
        while i < len(text) and (quote or not text[i].isspace()):
            c = text[i]
            if c == '\\' and i + 1 < len(text):
                arg += text[i + 1]
                i += 2
                continue
            if quote:
                if c == quote:
                    quote = None
                else:
                    arg += c
            elif c in '"\'':
                quote = c
            elif c == '#':
                return out + ([arg] if arg else [])
            else:
                arg += c
            i += 1
        if quote:
            sys.exit('unmatched %s in %r' % (quote, text))
        out.append(arg)

for line in open(sys.argv[1], encoding='utf-8', errors='surrogateescape').read().split('\n'):
    if line.startswith('#SBATCH'):
        for a in arguments(line[len('#SBATCH'):]):
            print(a.replace('\n', '\\n'))
    elif line.strip() and not line.lstrip().startswith('#'):
        break
