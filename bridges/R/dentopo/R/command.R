# Finding and running the dentopo command.
#
# The bridge talks to the command line program only: it writes no Python and
# embeds none.  Arguments go on the command line, the table comes back as CSV
# on the command's standard output (redirected into a temporary file), and
# per-vertex values as CSV files in a temporary directory.  Every temporary
# file is removed when the call returns, also after an error.

.dentopo_state <- new.env(parent = emptyenv())

INSTALL_HINT <- paste(
  "Install it with 'pip install .' in a clone of dentopo, or",
  "'pip install dentopo' (or 'pipx install dentopo') from PyPI,",
  "then put it on the PATH, set the DENTOPO environment variable to the",
  "program (e.g. DENTOPO=/path/to/venv/bin/dentopo), or call",
  "options(dentopo.command = \"/path/to/venv/bin/dentopo\")."
)

# Split a command given as one string: an existing file is one program
# (spaces and all); anything else is split on white space, so that
# "python3 -m dentopo" works.
# @noRd
split_command <- function(x) {
  if (!is.character(x) || length(x) == 0L || anyNA(x) || !all(nzchar(x))) {
    return(NULL)
  }
  if (length(x) > 1L || file.exists(x)) {
    return(x)
  }
  parts <- strsplit(trimws(x), "[[:space:]]+")[[1L]]
  parts[nzchar(parts)]
}

# Run a command with its output in temporary files; returns the exit
# status and the text of both streams.
# @noRd
run_program <- function(cmd, args, dir) {
  out <- file.path(dir, "stdout.txt")
  err <- file.path(dir, "stderr.txt")
  status <- suppressWarnings(system2(
    cmd[1L],  # system2 quotes the command itself
    c(shQuote(cmd[-1L]), shQuote(args)),
    stdout = out, stderr = err
  ))
  read_text <- function(path) {
    if (!file.exists(path)) return(character())
    readLines(path, warn = FALSE, encoding = "UTF-8")
  }
  list(status = status, stdout = out, stderr = read_text(err),
       stdout_text = function() read_text(out))
}

# Why a candidate command does not work, or NULL when `--version` answers.
# @noRd
probe_command <- function(cmd) {
  key <- paste(cmd, collapse = "\r")
  if (isTRUE(.dentopo_state$working[[key]])) return(NULL)
  if (!nzchar(Sys.which(cmd[1L]))) {
    return("no such program")
  }
  dir <- tempfile("dentopo-probe-")
  dir.create(dir)
  on.exit(unlink(dir, recursive = TRUE), add = TRUE)
  res <- tryCatch(run_program(cmd, "--version", dir),
                  error = function(e) conditionMessage(e))
  if (is.character(res)) return(res)
  said <- res$stdout_text()
  if (identical(res$status, 0L) && length(said) && startsWith(said[1L], "dentopo")) {
    if (is.null(.dentopo_state$working)) .dentopo_state$working <- list()
    .dentopo_state$working[[key]] <- TRUE
    return(NULL)
  }
  detail <- trimws(paste(c(said, res$stderr), collapse = " "))
  if (nchar(detail) > 200L) detail <- paste0(substr(detail, 1L, 200L), "...")
  sprintf("'--version' exited with status %s%s", res$status,
          if (nzchar(detail)) paste0(": ", detail) else "")
}

# The dentopo command the bridge runs
#
# Finds the \command{dentopo} program: first \code{getOption("dentopo.command")},
# then the \env{DENTOPO} environment variable, then \command{dentopo} on the
# \env{PATH}; the first that answers \code{dentopo --version} is used.
#
# Either setting may name the program (a path, spaces allowed), or be a
# command line split on white space such as \code{"python3 -m dentopo"};
# the option may also be a character vector (program, then its arguments).
# When a setting does not work but a later one does, a warning says so.
#
# @return The command as a character vector: the program, then any arguments
#   that come before dentopo's own.
# @examples
# \dontrun{
# options(dentopo.command = "~/venvs/dentopo/bin/dentopo")
# dentopo_command()
# }
# @export
dentopo_command <- function() {
  candidates <- list()
  opt <- getOption("dentopo.command")
  if (!is.null(opt)) {
    candidates[[length(candidates) + 1L]] <- list(
      source = "options(dentopo.command)", value = opt,
      cmd = split_command(path.expand(opt)))
  }
  env <- Sys.getenv("DENTOPO", "")
  if (nzchar(env)) {
    candidates[[length(candidates) + 1L]] <- list(
      source = "the DENTOPO environment variable", value = env,
      cmd = split_command(path.expand(env)))
  }
  on_path <- Sys.which("dentopo")
  candidates[[length(candidates) + 1L]] <- list(
    source = "the PATH", value = "dentopo",
    cmd = if (nzchar(on_path)) unname(on_path) else NULL)
  problems <- character()
  for (cand in candidates) {
    why <- if (is.null(cand$cmd)) {
      if (identical(cand$source, "the PATH")) "not found" else "not a command"
    } else {
      probe_command(cand$cmd)
    }
    if (is.null(why)) {
      if (length(problems)) {
        warning(sprintf("dentopo: using %s from %s; %s",
                        paste(cand$cmd, collapse = " "), cand$source,
                        paste(problems, collapse = "; ")), call. = FALSE)
      }
      return(cand$cmd)
    }
    problems <- c(problems, sprintf("%s ('%s') does not work: %s", cand$source,
                                    paste(cand$value, collapse = " "), why))
  }
  stop(sprintf("the dentopo command was not found (%s). %s",
               paste(problems, collapse = "; "), INSTALL_HINT), call. = FALSE)
}

# One command line option from an R value: NULL, NA and FALSE leave it out,
# TRUE is a bare flag, anything else is `--name value` (a vector becomes one
# comma-separated value; numbers with every digit needed to read them back).
# @noRd
as_option <- function(name, value) {
  if (!nzchar(name)) {
    stop("dentopo: every argument in ... must be named (the option it becomes)",
         call. = FALSE)
  }
  flag <- paste0("--", gsub("[._]", "-", name))
  if (is.null(value) || (length(value) == 1L && is.na(value)) ||
      identical(value, FALSE)) {
    return(character())
  }
  if (identical(value, TRUE)) return(flag)
  if (is.factor(value)) value <- as.character(value)
  if (!(is.numeric(value) || is.character(value)) || length(value) == 0L ||
      anyNA(value)) {
    stop(sprintf("dentopo: option %s wants TRUE/FALSE, numbers or text; got %s",
                 flag, paste(deparse(value), collapse = " ")), call. = FALSE)
  }
  text <- if (is.numeric(value)) vapply(value, format_number, "") else value
  c(flag, paste(text, collapse = ","))
}

# Shortest decimal text that reads back as the same double.
# @noRd
format_number <- function(x) {
  if (!is.finite(x)) return(as.character(x))
  for (digits in 15:17) {
    text <- formatC(x, digits = digits, format = "g")
    if (as.numeric(text) == x) break
  }
  trimws(text)
}

# The options of a call as command line arguments.
# @noRd
as_options <- function(options) {
  names <- names(options)
  if (length(options) && is.null(names)) names <- rep("", length(options))
  unlist(Map(as_option, names, options), use.names = FALSE)
}

# Paths as arguments after `--`, so a name starting with '-' or equal to a
# subcommand is still a path.
# @noRd
as_paths <- function(files) {
  if (!is.character(files) || anyNA(files)) {
    stop("dentopo: 'files' must be a character vector of mesh files, directories or globs",
         call. = FALSE)
  }
  if (length(files) == 0L) return(character())  # e.g. samples = TRUE alone
  c("--", path.expand(files))
}

# The command's message on a failed run: its stderr without argparse's
# usage block.
# @noRd
command_message <- function(lines) {
  keep <- character()
  in_usage <- FALSE
  for (line in lines) {
    if (startsWith(line, "usage:")) {
      in_usage <- TRUE
      next
    }
    if (in_usage && grepl("^[[:space:]]", line)) next
    in_usage <- FALSE
    if (nzchar(trimws(line))) keep <- c(keep, line)
  }
  paste(keep, collapse = "\n")
}

# Run dentopo with `args` in the work directory `dir`; returns the path of
# its standard output, or stops with its message when it computed nothing
# (exit status 2: usage error; 130: interrupted; anything else).  Exit
# status 1 (some file failed) is not an error here: its rows say why.
# @noRd
run_dentopo <- function(args, dir) {
  cmd <- dentopo_command()
  res <- run_program(cmd, args, dir)
  ok <- res$status %in% c(0L, 1L) && file.exists(res$stdout) &&
    file.size(res$stdout) > 0
  if (!ok) {
    said <- command_message(res$stderr)
    what <- switch(as.character(res$status),
                   "2" = "usage error",
                   "130" = "interrupted",
                   "failed")
    stop(sprintf("dentopo %s (exit status %s)%s", what, res$status,
                 if (nzchar(said)) paste0(": ", said) else ""), call. = FALSE)
  }
  res$stdout
}
