library(testthat)
library(dentopo)

test_check("dentopo")
