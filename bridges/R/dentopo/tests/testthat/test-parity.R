# The Python suite (tests/test_bridges.py) writes the values dentopo.ariaDNE
# gives in Python, and the message compute_batch gives for a corrupt file, to
# a CSV named by DENTOPO_PARITY_CSV; the bridge must reproduce them.

parity_table <- function() {
  path <- Sys.getenv("DENTOPO_PARITY_CSV")
  if (!nzchar(path)) skip("DENTOPO_PARITY_CSV not set (tests/test_bridges.py sets it)")
  utils::read.csv(path, colClasses = "character", na.strings = character(),
                  encoding = "UTF-8", fileEncoding = "UTF-8")
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
  message(sprintf("R parity, %s (%d meshes): max relative difference %.3g",
                  want$set[1L], nrow(want), worst))
}

test_that("the bridge gives Python's values on the bundled samples", {
  skip_without_dentopo()
  table <- parity_table()
  want <- table[table$set == "samples" & table$distance_type == "euclidean", ]
  skip_if(nrow(want) == 0L, "no sample rows in the parity table")
  check_parity(want)
})

test_that("the bridge gives Python's values on the shared meshes", {
  skip_without_dentopo()
  table <- parity_table()
  want <- table[table$set == "shared" & table$distance_type == "euclidean", ]
  skip_if(nrow(want) == 0L, "shared meshes absent (../shared/data/meshes)")
  check_parity(want)
})

test_that("error rows and their messages come through unchanged", {
  skip_without_dentopo()
  table <- parity_table()
  want <- table[table$set == "bad", ]
  skip_if(nrow(want) == 0L, "no error rows in the parity table")
  got <- dentopo_batch(want$file)
  expect_equal(got$status, rep("error", nrow(want)))
  expect_identical(got$error[match(want$file, got$file)], want$error)
})
