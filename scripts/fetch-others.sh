#!/usr/bin/env bash
# Fetch the shaders written by others that tests/others/SOURCES.md lists, each at its commit,
# into tests/others/ (or the folder REPROJ_OTHERS_CORPUS names), with a header comment naming
# repository, path, commit and license above the file's text (below its first line where that is
# GLSL's `#version`, which an ES shader must start with), which is kept as found.
#
#   bash scripts/fetch-others.sh               # from GitHub (raw files; an archive for a folder)
#   bash scripts/fetch-others.sh MIRROR        # from bare git directories MIRROR/OWNER+NAME/repo
#                                              # (or MIRROR/OWNER+NAME), no network
#
# SOURCES.md has two kinds of rows, told apart by their link: a file (`…/blob/COMMIT/PATH`) is
# written to the row's first column; a folder (`…/tree/COMMIT/DIR`, its text `DIR/**/*.EXT`)
# gives every `.EXT` file under DIR, written under the row's first column at its path in the
# repository. Rows of the "left out" table (no destination in backquotes) are skipped.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
sources=$root/tests/others/SOURCES.md
dest=${REPROJ_OTHERS_CORPUS:-$root/tests/others}
mirror=${1:-}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# The bare git directory of OWNER/NAME under the mirror.
git_dir() {
    local d=$mirror/${1/\//+}
    [[ -d $d/repo ]] && d=$d/repo
    [[ -d $d/objects ]] || { echo "fetch-others: no git directory for $1 under $mirror" >&2; exit 1; }
    echo "$d"
}

# The file PATH of REPO at COMMIT on stdout.
file_at() {
    local repo=$1 commit=$2 path=$3
    if [[ -n $mirror ]]; then
        git --git-dir="$(git_dir "$repo")" show "$commit:$path"
    else
        curl -sSfL "https://raw.githubusercontent.com/$repo/$commit/$path"
    fi
}

# The paths of every .EXT file under DIR of REPO at COMMIT, one a line.
files_under() {
    local repo=$1 commit=$2 dir=$3 ext=$4
    if [[ -n $mirror ]]; then
        git --git-dir="$(git_dir "$repo")" ls-tree -r --name-only "$commit" -- "$dir" |
            grep -E "\.$ext\$" || true
    else
        local unpacked=$tmp/${repo/\//+}-$commit
        if [[ ! -d $unpacked ]]; then
            mkdir -p "$unpacked"
            curl -sSfL "https://codeload.github.com/$repo/tar.gz/$commit" |
                tar -xz -C "$unpacked" --strip-components=1
        fi
        (cd "$unpacked" && find "$dir" -type f -name "*.$ext" | sort)
    fi
}

# Write PATH of REPO at COMMIT to OUT under its header.
write() {
    local repo=$1 commit=$2 path=$3 license=$4 out=$5 text
    mkdir -p "$(dirname "$out")"
    if [[ -z $mirror && -d $tmp/${repo/\//+}-$commit ]]; then
        text=$(cat "$tmp/${repo/\//+}-$commit/$path" && printf x) ||
            { echo "fetch-others: cannot read $path of $repo at $commit" >&2; exit 1; }
    else
        text=$(file_at "$repo" "$commit" "$path" && printf x) ||
            { echo "fetch-others: cannot read $path of $repo at $commit" >&2; exit 1; }
    fi
    text=${text%x}
    # GLSL's `#version` stays the first line (an ES shader may have nothing before it).
    local version=""
    if [[ $text == "#version"* ]]; then
        version=${text%%$'\n'*}$'\n'
        text=${text#*$'\n'}
    fi
    {
        printf '%s' "$version"
        printf '// Written by others, kept as found around this header (reproj tests/others/SOURCES.md).\n'
        printf '// repository: https://github.com/%s\n// path: %s\n// commit: %s\n// license: %s\n' \
            "$repo" "$path" "$commit" "$license"
        printf '%s' "$text"
    } >"$out"
}

files=0
folders=0
# A row: | `DEST` | OWNER/NAME | [`TEXT`](https://github.com/OWNER/NAME/(blob|tree)/COMMIT/PATH) @ `…` | LICENSE |
row='^\| `([^`]+)` \| ([^ |]+) \| \[`([^`]+)`\]\(https://github\.com/[^/]+/[^/]+/(blob|tree)/([0-9a-f]{40})/([^)]+)\) @ `[0-9a-f]+` \| ([^|]+) \|'
while IFS= read -r line; do
    [[ $line =~ $row ]] || continue
    out=${BASH_REMATCH[1]} repo=${BASH_REMATCH[2]} text=${BASH_REMATCH[3]}
    kind=${BASH_REMATCH[4]} commit=${BASH_REMATCH[5]} path=${BASH_REMATCH[6]}
    license=${BASH_REMATCH[7]%"${BASH_REMATCH[7]##*[! ]}"}
    if [[ $kind == blob ]]; then
        write "$repo" "$commit" "$path" "$license" "$dest/$out"
        files=$((files + 1))
    else
        ext=${text##*.}
        while IFS= read -r f; do
            [[ -n $f ]] || continue
            write "$repo" "$commit" "$f" "$license" "$dest/${out%/}/$f"
        done < <(files_under "$repo" "$commit" "$path" "$ext")
        folders=$((folders + 1))
    fi
done <"$sources"
echo "fetch-others: $files files and $folders folders into $dest"
