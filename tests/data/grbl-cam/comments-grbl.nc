; every comment style grbl 1.1 reads (protocol.c)
(a comment in parentheses)
G21 G90 ; a semicolon comment after words
G0 X1 (a comment between words) Y2
G0 X2 (a comment with ; a semicolon inside) Y3
G0 X3 (a comment left open to the end of the line
(tool: 3.175 mm ; flat end mill)
G1 X4 F100 ;(a parenthesis inside a semicolon comment
M2
