"""What development history looks like in a page or a comment: numbered rounds of work, issue numbers and
targets, stories of how a figure changed. The docs and the code state what is, not how it came to be."""
import re

HISTORY = re.compile(
    r"\b(?:round|session|sprint|pass of work) \d+\b|\bissue\s*#?\d+|\bthe issue'?s? (?:target|asks?|goal|list)\b|"
    r"\bwhat changed\b|"
    r"\bsince (?:the )?(?:last|previous) (?:round|session|version|commit|change)\b|"
    r"\b(?:before|after) (?:this|the) (?:change|fix|commit|refactor(?:ing)?)\b|\bused to (?:be|take|give)\b|"
    r"\bpreviously\b|\(was [\d.]+ ?(?:s|x|%|GB|MB)|\bbefore/after\b", re.I)
