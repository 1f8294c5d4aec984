dentopo_vertices <- function(file, ...) {
  if (!is.character(file) || length(file) != 1L || is.na(file)) {
    stop("dentopo_vertices: 'file' must be the path of one mesh file", call. = FALSE)
  }
  if (dir.exists(file)) {
    stop(sprintf("dentopo_vertices: '%s' is a directory; give one mesh file", file),
         call. = FALSE)
  }
  options <- list(...)
  if (any(names(options) %in% c("output", "o", "per_vertex", "per_vertex_format"))) {
    stop("dentopo_vertices manages 'output' and 'per_vertex' itself", call. = FALSE)
  }
  dir <- tempfile("dentopo-")
  dir.create(dir)
  on.exit(unlink(dir, recursive = TRUE), add = TRUE)
  values <- file.path(dir, "values")
  args <- c("--quiet", "--output", "-", "--per-vertex", values,
            "--per-vertex-format", "csv", as_options(options), as_paths(file))
  row <- read_dentopo_csv(run_dentopo(args, dir))
  if (nrow(row) != 1L) {
    stop(sprintf("dentopo_vertices: '%s' gave %d rows; give one mesh file",
                 file, nrow(row)), call. = FALSE)
  }
  if (!identical(row$status, "ok")) {
    stop(row$error, call. = FALSE)
  }
  written <- list.files(values, pattern = "\\.dentopo\\.csv$", full.names = TRUE)
  if (length(written) != 1L) {
    stop(sprintf("dentopo_vertices: expected one per-vertex CSV from dentopo, found %d",
                 length(written)), call. = FALSE)
  }
  vertices <- read_dentopo_csv(written)
  attr(vertices, "summary") <- row
  vertices
}
