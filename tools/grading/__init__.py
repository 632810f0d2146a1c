"""The grader's parts (tools/grade.py holds the commands): running tests in a sandbox with limits
(running, sandbox, guard), building what is graded (building) and reporting (reports)."""


class GradeError(Exception):
    """The grading itself cannot go on (bad arguments, missing binary, ...)."""
