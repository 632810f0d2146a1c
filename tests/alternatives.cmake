# Correct alternatives of the hooks (tests/alternatives/*.json): each a variant that must score full marks.
