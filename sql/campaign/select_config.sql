SELECT config FROM campaign WHERE id = 1
