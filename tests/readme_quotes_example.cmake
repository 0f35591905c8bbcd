# Fails unless README.md contains the file SNIPPET verbatim (inside its ```cpp block), so the
# README's usage example cannot drift from the program the tests compile and run.
file(READ "${README}" readme)
file(READ "${SNIPPET}" snippet)
string(FIND "${readme}" "${snippet}" position)
if(position EQUAL -1)
  message(FATAL_ERROR "README.md does not quote ${SNIPPET} verbatim; copy the file into its usage example")
endif()
message(STATUS "README.md quotes ${SNIPPET}")
