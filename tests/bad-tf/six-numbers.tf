# expect: 2: a control point is five numbers: value r g b alpha \(got 6 words\)
0 0 0 0 0 0
