"""The paper's eleven experiments, by system in the paper's order (``vslsp experiment --list``)."""

PAPER = [
    "house-roof",
    "alphabet-ordering",
    "animal-puzzle",
    "tower-of-hanoi",
    "animals-vs-machines",
    "domino",
    "table-cleaning",
    "stacking",
    "simple-vsl-task",
    "keep-all-near",
    "pull-in-order",
]
