# expect: 2: a control point is five numbers: value r g b alpha \(got 4 words\)
0 0 0 0
