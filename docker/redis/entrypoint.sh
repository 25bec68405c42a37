#!/bin/sh
# Entry point of the Debian-based Redis image, as the official image's: options alone run
# redis-server with them, and protected mode is off unless the command line sets it (the
# server is reached over the compose network only, never published).
set -e
if [ "${1#-}" != "$1" ]; then
    set -- redis-server "$@"
fi
if [ "$1" = redis-server ]; then
    case " $* " in
        *" --protected-mode "*) ;;
        *) set -- "$@" --protected-mode no ;;
    esac
fi
exec "$@"
