# Writes a tool's --help to a file: cmake -DTOOL=<exe> -DOUT=<file> -P write_help.cmake.
# Run when the tool is built, so the option matrix (bad_input_values_test.cpp) reads the help it
# derives its cases from without starting three tools in every test process.
execute_process(COMMAND "${TOOL}" --help OUTPUT_FILE "${OUT}.tmp" RESULT_VARIABLE result)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "${TOOL} --help exited with ${result}")
endif()
file(RENAME "${OUT}.tmp" "${OUT}")
