# Columns that hold text whatever their values (the rest become numbers when
# every value reads as one).
TEXT_COLUMNS <- c("file", "File", "status", "error", "warnings", "distance_type",
                  "sign_method", "method", "orientation", "orient", "protocol")

# Read the command's CSV: every column as text first, so that an error message
# with commas, quotes or line breaks comes through unchanged; then each
# column that holds only numbers (or nothing) as doubles, read from the
# shortest-repr text the command writes, so exactly.  A cell that begins
# with an apostrophe had one put there by the command (so that a spreadsheet
# does not run a name such as "=HYPERLINK(...).ply" as a formula): exactly
# one is removed, as dentopo's read_table does.
read_dentopo_csv <- function(path) {
  table <- utils::read.csv(path, colClasses = "character", na.strings = character(),
                           check.names = FALSE, encoding = "UTF-8",
                           fileEncoding = "UTF-8", strip.white = FALSE)
  for (name in names(table)) {
    text <- sub("^'", "", table[[name]])
    empty <- !nzchar(text)
    if (name %in% TEXT_COLUMNS) {
      text[empty] <- NA_character_
      table[[name]] <- text
      next
    }
    numbers <- suppressWarnings(as.numeric(text))
    if (!anyNA(numbers[!empty])) {
      numbers[empty] <- NA_real_
      # Python writes an integer without '.' or exponent (a float never so):
      # such columns (vertices, faces, vertex, sign) come back as integers.
      whole <- all(grepl("^-?[0-9]+$", text[!empty])) &&
        all(abs(numbers[!empty]) <= .Machine$integer.max)
      table[[name]] <- if (whole && any(!empty)) as.integer(numbers) else numbers
    } else {
      text[empty] <- NA_character_
      table[[name]] <- text
    }
  }
  table
}

dentopo_batch <- function(files, metrics = "ariadne", bandwidth = 0.08, ...,
                          columns = NULL, jobs = 1) {
  options <- list(...)
  if (any(names(options) %in% c("output", "o"))) {
    stop("dentopo_batch returns the table: write it with write.csv() rather than 'output'",
         call. = FALSE)
  }
  if (!is.character(metrics) || length(metrics) == 0L || anyNA(metrics)) {
    stop("dentopo: 'metrics' must be a character vector such as \"ariadne\"",
         call. = FALSE)
  }
  # "ariadne" alone is what the command computes by default: it is passed only
  # when something else is asked for, so that this works with commands that
  # predate --metrics.
  metrics_option <- if (identical(unique(tolower(metrics)), "ariadne")) NULL else metrics
  args <- c("--quiet", "--output", "-",
            as_options(c(list(metrics = metrics_option, bandwidth = bandwidth,
                              columns = columns, jobs = jobs), options)),
            as_paths(files))
  dir <- tempfile("dentopo-")
  dir.create(dir)
  on.exit(unlink(dir, recursive = TRUE), add = TRUE)
  read_dentopo_csv(run_dentopo(args, dir))
}
