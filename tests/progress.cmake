# The worksheets' "Before you start" checks, run against variants with the earlier worksheets done.
