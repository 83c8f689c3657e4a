# The .gi format's constants in web/ agree with the C headers and tables they copy
# (tests/format_constants.py reads both sides' source): issue 38, item 4.
python3 "$ROOT/tests/format_constants.py" "$ROOT"
