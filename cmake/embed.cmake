# stepstone_embed_files(OUTPUT <cpp> FUNCTION <name> BASE <dir> FILES <f>...)
# Writes a C++ source defining `std::span<const stepstone::EmbeddedFile> <name>()`
# that returns every file's path (relative to BASE) and text, sorted by path.
# The text is embedded as raw-string literals, so the binary needs no data directory.
set(STEPSTONE_EMBED_SCRIPT ${CMAKE_CURRENT_LIST_DIR}/embed_files.cmake)

function(stepstone_embed_files)
    cmake_parse_arguments(ARG "" "OUTPUT;FUNCTION;BASE" "FILES" ${ARGN})
    list(SORT ARG_FILES)
    string(REPLACE ";" "|" files_arg "${ARG_FILES}")
    add_custom_command(
        OUTPUT ${ARG_OUTPUT}
        COMMAND ${CMAKE_COMMAND} -DOUTPUT=${ARG_OUTPUT} -DFUNCTION=${ARG_FUNCTION}
                -DBASE=${ARG_BASE} "-DFILES=${files_arg}" -P ${STEPSTONE_EMBED_SCRIPT}
        DEPENDS ${ARG_FILES} ${STEPSTONE_EMBED_SCRIPT}
        COMMENT "Embedding ${ARG_FUNCTION}"
        VERBATIM)
endfunction()
