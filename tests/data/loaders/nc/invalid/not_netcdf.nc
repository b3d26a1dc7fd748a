CDF but not really
