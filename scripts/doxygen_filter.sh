#!/bin/sh
# Doxygen INPUT_FILTER: gyrocomp's headers document each name with plain // comments (the style
# of the project style guide); Doxygen reads /// ones. A comment line above a declaration
# becomes ///, and a trailing "// ..." after a member or enumerator becomes ///<, as does one
# after a one-line inline function body ("int f() const { return n_; }  // ..."); a trailing
# "// NOLINT..." is a note to clang-tidy and stays a plain comment. The code before a trailing
# comment may hold string literals ("gyrocomp") and single slashes (1.0 / 3.0).
# Every header opens with a comment block right above "#pragma once": that block describes the
# file, so the "#pragma once" line (not needed by Doxygen) becomes "/// \file", which makes the
# block the file's documentation instead of a part of namespace gyrocomp's (line numbers kept).
exec sed -E \
  -e 's#^([[:space:]]*)//([^/!]|$)#\1///\2#' \
  -e 's#^(([^/"]|/[^/"]|"[^"]*")*[;,{])[[:space:]]*//[[:space:]]#\1  ///< #' \
  -e 's#^(([^/"]|/[^/"]|"[^"]*")*\{([^/"]|/[^/"]|"[^"]*")*\})[[:space:]]*//[[:space:]]#\1  ///< #' \
  -e 's#///< NOLINT#// NOLINT#' \
  -e 's#^\#pragma once$#/// \\file#' \
  "$1"
