# SPDX-License-Identifier: GPL-3.0-or-later
# Run by `cmake --install` (and so by cpack): writes the unit AMEOTO_UNIT_SOURCE to AMEOTO_UNIT_OUTPUT with
# ExecStart= naming the ameotod of the prefix being installed (CMAKE_INSTALL_PREFIX at install time: /usr
# in the Debian package, /usr/local for a plain `cmake --install`). The units in systemd/ name
# /usr/local/bin/ameotod, where docs/systemd.md installs by hand; their opening comment, which says how to
# copy them by hand, is replaced by one that says where this copy came from.
file(READ "${AMEOTO_UNIT_SOURCE}" unit)
set(from "ExecStart=/usr/local/bin/ameotod ")
set(to "ExecStart=${CMAKE_INSTALL_PREFIX}/${AMEOTO_BINDIR}/ameotod ")
string(FIND "${unit}" "${from}" at)
if(at EQUAL -1)
  message(FATAL_ERROR "${AMEOTO_UNIT_SOURCE} has no '${from}...' line to point at the installed ameotod")
endif()
string(REPLACE "${from}" "${to}" unit "${unit}")
if(NOT unit MATCHES "^(#[^\n]*\n)+\n")
  message(FATAL_ERROR "${AMEOTO_UNIT_SOURCE} does not open with a comment block and a blank line")
endif()
string(LENGTH "${CMAKE_MATCH_0}" opening)
string(SUBSTRING "${unit}" ${opening} -1 unit)
file(WRITE "${AMEOTO_UNIT_OUTPUT}"
  "# SPDX-License-Identifier: GPL-3.0-or-later\n"
  "# ameotod's ${AMEOTO_UNIT_KIND} unit, installed with ameoto: ExecStart= runs ${CMAKE_INSTALL_PREFIX}/${AMEOTO_BINDIR}/ameotod.\n"
  "# Keep this file as it is: change settings with a drop-in (${AMEOTO_UNIT_EDIT}); see\n"
  "# /usr/share/doc/ameoto/docs/systemd.md (in the sources: docs/systemd.md).\n"
  "\n"
  "${unit}")
