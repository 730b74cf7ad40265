# Doxygen input filter for the public C headers: their comments are plain C
# comments (the headers are read as text by hosts first), so this marks them
# as documentation on the fly, keeping every line where it is:
#   - the file's first comment becomes its \file description;
#   - a comment that starts a line documents what follows it;
#   - a comment after code on the same line documents that code (/**<);
#   - section rules ("/* ---- name */") stay plain comments.
{
    line = $0
    if (!in_comment) {
        start = index(line, "/*")
        if (start > 0) {
            before = substr(line, 1, start - 1)
            rest = substr(line, start + 2)
            if (rest ~ /^ -{3,}/) {
                marker = "/*"
            } else if (!seen_comment) {
                file = FILENAME
                sub(/.*\//, "", file)
                marker = "/** \\file " file " "
            } else if (before ~ /^[ \t]*$/) {
                marker = "/**"
            } else {
                marker = "/**<"
            }
            seen_comment = 1
            line = before marker rest
            in_comment = index(rest, "*/") == 0
        }
    } else if (index(line, "*/") > 0) {
        in_comment = 0
    }
    print line
}
