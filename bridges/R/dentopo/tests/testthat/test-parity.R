# The Python suite (tests/test_bridges.py) writes, into the directory named by
# DENTOPO_PARITY_DIR, the values dentopo.ariaDNE gives in Python
# (expected.csv) and a corrupt file with the message compute_batch gives for
# it (bad_file.txt, bad_error.txt); the bridge must reproduce them.

parity_file <- function(name) {
  dir <- Sys.getenv("DENTOPO_PARITY_DIR")
  if (!nzchar(dir)) skip("DENTOPO_PARITY_DIR not set (tests/test_bridges.py sets it)")
  file.path(dir, name)
}

parity_rows <- function(set) {
  table <- utils::read.csv(parity_file("expected.csv"), colClasses = "character",
                           encoding = "UTF-8", fileEncoding = "UTF-8")
  table[table$set == set & table$distance_type == "euclidean", ]
}

read_utf8 <- function(path) {
  text <- readChar(path, file.size(path), useBytes = TRUE)
  Encoding(text) <- "UTF-8"
  text
}

check_parity <- function(want) {
  got <- dentopo_batch(want$file)
  got <- got[match(normalizePath(want$file), normalizePath(got$file)), ]
  expect_equal(got$status, rep("ok", nrow(want)))
  worst <- 0
  for (column in c("dne", "positive_dne", "negative_dne")) {
    difference <- max_relative_difference(got[[column]], as.numeric(want[[column]]))
    expect_lte(difference, 1e-12, label = column)
    worst <- max(worst, difference)
  }
  # shown by tests/test_bridges.py
  cat(sprintf("R parity, %s (%d meshes): max relative difference %.3g\n",
              want$set[1L], nrow(want), worst))
}

test_that("the bridge gives Python's values on the bundled samples", {
  skip_without_dentopo()
  want <- parity_rows("samples")
  skip_if(nrow(want) == 0L, "no sample rows in the parity table")
  check_parity(want)
})

test_that("the bridge gives Python's values on the shared meshes", {
  skip_without_dentopo()
  want <- parity_rows("shared")
  skip_if(nrow(want) == 0L, "shared meshes absent (../shared/data/meshes)")
  check_parity(want)
})

test_that("an error row and its message come through unchanged", {
  skip_without_dentopo()
  bad <- read_utf8(parity_file("bad_file.txt"))
  got <- dentopo_batch(bad)
  expect_equal(got$file, bad)
  expect_equal(got$status, "error")
  expect_identical(got$error, read_utf8(parity_file("bad_error.txt")))
})
