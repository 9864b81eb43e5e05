executable: no_such_env_program -e x.e spec
communication type: files
