# bash completion for cairn: commands, each command's options (read from `cairn COMMAND --help`,
# so they never fall out of step with the program), option values where they are a fixed list,
# and file names elsewhere (JSON files for FILE and --plan, directories for --figures).
# Install: source it from ~/.bashrc, or copy it to
# ~/.local/share/bash-completion/completions/cairn.
_cairn() {
    local cur prev cmd
    cur=${COMP_WORDS[COMP_CWORD]}
    prev=${COMP_WORDS[COMP_CWORD - 1]}
    COMPREPLY=()
    if [ "$COMP_CWORD" -eq 1 ]; then
        mapfile -t COMPREPLY < <(compgen -W "check simulate plan margin directions contacts lcp export --help --version" -- "$cur")
        return
    fi
    cmd=${COMP_WORDS[1]}
    case $prev in
        --solver) mapfile -t COMPREPLY < <(compgen -W "auto lemke pivot" -- "$cur"); return ;;
        --support) mapfile -t COMPREPLY < <(compgen -W "hold push both" -- "$cur"); return ;;
        --figures) mapfile -t COMPREPLY < <(compgen -d -- "$cur"); return ;;
        --to) mapfile -t COMPREPLY < <(compgen -W "obj gltf" -- "$cur"); return ;;
        --only) mapfile -t COMPREPLY < <(compgen -W "friction tilt lateral friction,tilt tilt,lateral friction,tilt,lateral" -- "$cur"); return ;;
        --figure | --csv | --lcp-out | --html) mapfile -t COMPREPLY < <(compgen -f -- "$cur"); return ;;
        --plan) mapfile -t COMPREPLY < <(compgen -f -X '!*.json' -- "$cur"; compgen -d -- "$cur"); return ;;
        --max-states | --max-seconds | --max-sub | --search-budget | --reading | --repeat | --parts | \
        --pair | --axis | --direction | --margin-tol) return ;;
    esac
    if [[ $cur == -* ]]; then
        local opts
        opts=$("${COMP_WORDS[0]}" "$cmd" --help 2>/dev/null | sed -n '/^usage:/,/^$/p' | grep -o -- '--[a-z-]*' | sort -u)
        mapfile -t COMPREPLY < <(compgen -W "$opts --help --quiet" -- "$cur")
        return
    fi
    if [ "$cmd" = lcp ]; then
        mapfile -t COMPREPLY < <(compgen -f -X '!*.lcp' -- "$cur"; compgen -d -- "$cur")
    else
        mapfile -t COMPREPLY < <(compgen -f -X '!*.json' -- "$cur"; compgen -d -- "$cur")
    fi
}
complete -o filenames -F _cairn cairn
