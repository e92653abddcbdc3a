# Writes OUTPUT (tl_revision.h) with the git revision of SOURCE_DIR ("-dirty"
# appended for uncommitted changes), or "unknown" outside git or without
# GIT.  Run at every build; the file is rewritten only when the revision
# changes, so only the file that includes it is recompiled then.
set(rev unknown)
if(GIT)
  execute_process(COMMAND "${GIT}" -C "${SOURCE_DIR}" describe --always --dirty --abbrev=12
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_QUIET OUTPUT_STRIP_TRAILING_WHITESPACE)
  if(rc EQUAL 0 AND NOT out STREQUAL "")
    set(rev "${out}")
  endif()
endif()
set(text "/* Generated at build time by cmake/TalusRevision.cmake. */\n#define TALUS_REVISION \"${rev}\"\n")
set(old "")
if(EXISTS "${OUTPUT}")
  file(READ "${OUTPUT}" old)
endif()
if(NOT old STREQUAL text)
  file(WRITE "${OUTPUT}" "${text}")
endif()
