# expect: no control points
# only comments

