#!/usr/bin/env bash
# The include layering of docs/architecture.md holds: every #include "..." of src/ and
# include/rcfd/ goes to the file's own room or to one its "Room order" line lets it include
# (nothing points up or sideways).  A public header belongs to the room whose row of the
# rooms table names it.  Reads the order and the table from the document itself, so that
# a change to either is checked against the code.
# usage: test_include_rooms.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -u
source_dir=$4
source "$(dirname "${BASH_SOURCE[0]}")/script_helpers.sh"
doc=$source_dir/docs/architecture.md
cd "$source_dir" || exit 1

declare -A allowed public
# "    room: lower rooms..." lines of the fenced block after "## Room order".
while read -r room rest; do
  allowed[${room%:}]=" ${room%:} $rest "
done < <(awk '/^## Room order/ { on = 1 } on && /^```/ { n++; next } on && n == 1 && /:/' "$doc")
# The public headers of each room: `name.hpp` in the third column of the rooms table.
while IFS='|' read -r _ room _ headers _; do
  room=$(sed -E 's/.*`src\/([a-z_]+).*/\1/' <<<"$room")
  for h in $(grep -oE '`[a-z_]+\.hpp`' <<<"$headers" | tr -d '`'); do public[$h]=$room; done
done < <(grep -E '^\| `src/' "$doc")
[ ${#allowed[@]} -ge 12 ] && [ ${#public[@]} -ge 20 ] && ok ||
  { fail "docs/architecture.md: found ${#allowed[@]} rooms in its Room order and ${#public[@]} public headers"; exit 1; }

room_of() { # room of a file of the tree, or of an include "dir/x.hpp" / "rcfd/x.hpp"
  case $1 in
  src/*) cut -d/ -f2 <<<"$1" ;;
  include/rcfd/* | rcfd/*) echo "${public[$(basename "$1")]:-?}" ;;
  *) cut -d/ -f1 <<<"$1" ;;
  esac
}

checked=0
while IFS= read -r file; do
  from=$(room_of "$file")
  [ "$from" = "?" ] && { fail "$file: a public header in no row of the rooms table"; continue; }
  [ -n "${allowed[$from]:-}" ] || { fail "$file: room '$from' is not in the Room order"; continue; }
  while IFS=: read -r line target; do
    to=$(room_of "$target")
    checked=$((checked + 1))
    if [ "$to" = "?" ]; then
      fail "$file:$line includes $target, a public header in no row of the rooms table"
    elif [[ ${allowed[$from]} != *" $to "* ]]; then
      fail "$file:$line: room $from includes $target of room $to, which its Room order line does not list"
    fi
  done < <(grep -nE '^#include "' "$file" | sed -E 's/^([0-9]+):#include "([^"]+)".*/\1:\2/')
done < <(find src include/rcfd -name '*.hpp' -o -name '*.cpp' | sort)
[ $checked -gt 300 ] && ok || fail "only $checked includes found"
echo "$passed passed, $failures failed ($checked includes)"
[ $failures -eq 0 ]
