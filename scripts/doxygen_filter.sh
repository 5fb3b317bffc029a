#!/bin/sh
# Doxygen INPUT_FILTER: gyrocomp's headers document each name with plain // comments (the style
# of the project style guide); Doxygen reads /// ones. A comment line above a declaration
# becomes ///, and a trailing "// ..." after a member or enumerator becomes ///<.
exec sed -E \
  -e 's#^([[:space:]]*)//([^/!]|$)#\1///\2#' \
  -e 's#^([^/"]*[;,{])[[:space:]]*//[[:space:]]#\1  ///< #' \
  "$1"
