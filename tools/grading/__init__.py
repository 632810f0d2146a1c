"""The grader's parts (tools/grade.py holds the commands): running each test as the trusted checker
and the submission's engine in the sandbox (running, sandbox, cgroups, guard), building what is
graded (building: submissions compiled in the sandbox) and reporting (reports)."""


class GradeError(Exception):
    """The grading itself cannot go on (bad arguments, missing binary, ...)."""
